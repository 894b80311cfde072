#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <superloc/core/config.h>

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
