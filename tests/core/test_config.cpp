#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <superloc/core/config.h>
#include <superloc_testing/testing.h>

#include <fstream>

using namespace superloc;

namespace {
struct DemoParams : public mrpt::config::CLoadableOptions {
    double voxel = 0.5;  ///< [m]
    bool enabled = true;
    std::string name = "x";
    void loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) override {
        MRPT_LOAD_CONFIG_VAR(voxel, double, c, s);
        MRPT_LOAD_CONFIG_VAR(enabled, bool, c, s);
        name = c.read_string(s, "name", name);
    }
    void saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const override {
        MRPT_SAVE_CONFIG_VAR_COMMENT(voxel, "[m] voxel size");
        MRPT_SAVE_CONFIG_VAR_COMMENT(enabled, "switch");
        c.write(s, "name", name);
    }
    void validate() const {
        if (voxel <= 0) throw ConfigError("[demo] voxel must be > 0");
    }
};
}  // namespace

TEST(Config, AcceptsKnownKeysWithComments) {
    mrpt::config::CConfigFileMemory c("[demo]\nvoxel = 0.25  // half\nenabled=false\nname=abc\n");
    const auto p = loadParams<DemoParams>(c, "demo", "t.ini");
    EXPECT_DOUBLE_EQ(p.voxel, 0.25);
    EXPECT_FALSE(p.enabled);
    EXPECT_EQ(p.name, "abc");
}

TEST(Config, RejectsUnknownKeyNamingIt) {
    mrpt::config::CConfigFileMemory c("[demo]\nvoxle = 0.25\n");
    try {
        loadParams<DemoParams>(c, "demo", "t.ini");
        FAIL() << "no error";
    } catch (const ConfigError& e) {
        EXPECT_NE(std::string(e.what()).find("t.ini: unknown key 'voxle' in section [demo]"),
                  std::string::npos)
            << e.what();
    }
}

TEST(Config, RejectsWrongTypes) {
    mrpt::config::CConfigFileMemory c1("[demo]\nvoxel = abc\n");
    EXPECT_THROW(loadParams<DemoParams>(c1, "demo", "t.ini"), ConfigError);
    mrpt::config::CConfigFileMemory c2("[demo]\nenabled = maybe\n");
    EXPECT_THROW(loadParams<DemoParams>(c2, "demo", "t.ini"), ConfigError);
    mrpt::config::CConfigFileMemory c3("[demo]\nvoxel = -1\n");
    EXPECT_THROW(loadParams<DemoParams>(c3, "demo", "t.ini"), ConfigError);
}

TEST(Config, WholeNumberKeysRejectFractions) {
    struct IntParams : public mrpt::config::CLoadableOptions {
        int rounds = 3;
        double scale = 2.0;
        void loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) override {
            MRPT_LOAD_CONFIG_VAR(rounds, int, c, s);
            MRPT_LOAD_CONFIG_VAR(scale, double, c, s);
        }
        void saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const override {
            MRPT_SAVE_CONFIG_VAR_COMMENT(rounds, "count");
            MRPT_SAVE_CONFIG_VAR_COMMENT(scale, "[m]");
        }
        void validate() const {}
    };
    for (const char* bad : {"2000.7", "1e3", "3 rounds", "0x10", ""}) {
        mrpt::config::CConfigFileMemory c(std::string("[demo]\nrounds = ") + bad + "\n");
        const std::string m = superloc::testing::errorOf([&] { loadParams<IntParams>(c, "demo", "t.ini"); });
        EXPECT_NE(m.find("t.ini: [demo] rounds = '"), std::string::npos) << bad << ": " << m;
        EXPECT_NE(m.find("is not a whole number"), std::string::npos) << bad << ": " << m;
    }
    mrpt::config::CConfigFileMemory ok("[demo]\nrounds = -12 // c\nscale = 3\n");
    EXPECT_EQ(loadParams<IntParams>(ok, "demo", "t.ini").rounds, -12);
    EXPECT_DOUBLE_EQ(loadParams<IntParams>(ok, "demo", "t.ini").scale, 3.0);  // a real key takes "3"
}

// What MRPT's parser would take silently (issue 36): each is an error naming file and line.
TEST(Config, IniTextErrorsNameFileAndLine) {
    const auto error = [](const std::string& text) {
        return superloc::testing::errorOf([&] { checkIniText(text, "f.ini"); });
    };
    EXPECT_EQ(error("[localization\nmethod = icp\n"),
              "f.ini:1: section header '[localization' has no closing ']'");
    EXPECT_EQ(error("; c\nmethod = icp\n[localization]\n"), "f.ini:2: key 'method' before any [section]");
    EXPECT_EQ(error("[a]\nx = 1\n[b]\nx = 2\n[A]\nX = 3\n"),
              "f.ini:6: [A] X is given twice (also on line 2): keep one");
    EXPECT_EQ(error("[a]\nx 1\n"), "f.ini:2: 'x 1' is not key = value (in section [a])");
    EXPECT_EQ(error("[]\n"), "f.ini:1: section header '[]' has no name");
    EXPECT_EQ(error("[a] b\n"), "f.ini:1: text after the section header '[a] b'");
    EXPECT_EQ(error("[a]\n= 1\n"), "f.ini:2: '= 1' has no key before '='");
    // Fine: comments anywhere, blank lines, CRLF, MRPT's @define, a comment after a header.
    EXPECT_EQ(error("# c\r\n\n@define N 3\n[a] ; c\r\n  x = ${N} // c\n// c\n[b]\nx = 2\n"), "");
}

TEST(Config, UnknownSectionsAndSetSectionsAreErrors) {
    const std::string dir = superloc::testing::freshDir("config_sections");
    const std::string path = dir + "/a.ini";
    const IniSections known{"superloc-x", {"run", "map"}, {"eval"}, {"seq."}};
    const auto check = [&](const std::string& text, const std::vector<std::string>& sets) {
        std::ofstream(path) << text;
        mrpt::config::CConfigFileMemory c;
        loadIniFile(c, path);
        for (const auto& s : sets) applyOverride(c, s);
        return superloc::testing::errorOf([&] { checkSections(c, known, path, sets); });
    };
    EXPECT_EQ(check("[run]\n[Map]\n[eval]\n[seq.a]\nk = 1\n", {"map.voxel=1"}), "");
    EXPECT_EQ(check("[run]\n\n[rnu]\nk = 1\n", {}),
              path + ":3: unknown section [rnu] (superloc-x reads [run], [map], [seq.*])");
    EXPECT_EQ(check("[run]\n", {"mpa.voxel=1"}),
              "--set 'mpa.voxel=1': superloc-x has no section [mpa] (it reads [run], [map], [seq.*])");
    // A section another app reads is fine in the file, not in a --set of this app.
    EXPECT_NE(check("[run]\n", {"eval.align=true"}).find("no section [eval]"), std::string::npos);
}

TEST(Config, OverrideSyntax) {
    mrpt::config::CConfigFileMemory c;
    applyOverride(c, "demo.voxel=2");
    EXPECT_DOUBLE_EQ(loadParams<DemoParams>(c, "demo", "--set").voxel, 2.0);
    EXPECT_THROW(applyOverride(c, "voxel=2"), ConfigError);
    EXPECT_THROW(applyOverride(c, "demo.voxel"), ConfigError);
}

TEST(Config, MalformedEvalExpressionIsAOneLineConfigError) {
    // Found by tests/fuzz/fuzz_ini.cpp: MRPT's INI parser evaluates $eval{...} while parsing,
    // and its error for a malformed expression spans several lines with a call trace.
    mrpt::config::CConfigFileMemory cfg;
    try {
        setIniContent(cfg, "[localization]\nrounds = $eval{3 +* (}\n", "bad.ini");
        ADD_FAILURE() << "no error";
    } catch (const ConfigError& e) {
        const std::string msg = e.what();
        EXPECT_EQ(msg.rfind("bad.ini: ", 0), 0u) << msg;
        EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
    }
    setIniContent(cfg, "[localization]\nrounds = $eval{3+1}\n", "good.ini");
    EXPECT_EQ(cfg.read_int("localization", "rounds", 0), 4);
}
