// The user's configuration (doc/parameters.md): ini/localize.ini holds at most 40 keys, each one
// --dump-config knows and each at its code default (so the file is a view of the knobs a user
// tunes, and dropping a key changes no run); doc/parameters.md lists every key --dump-config
// prints, once, with the default it prints and whether ini/localize.ini holds it.
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <superloc/app/localize_app.h>
#include <superloc/core/config.h>
#include <superloc_testing/testing.h>

#include <cmath>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

using superloc::app::LocalizeApp;

namespace {

using Key = std::pair<std::string, std::string>;  // section, key

std::string readText(const std::string& path) {
    std::ifstream f(path);
    std::stringstream s;
    s << f.rdbuf();
    return s.str();
}

/// --dump-config of `ini`.
std::string dumpOf(const std::string& ini) {
    LocalizeApp app;
    app.setMinLoggingLevel(mrpt::system::LVL_ERROR);
    EXPECT_EQ(app.initialize(std::vector<std::string>{ini, "--dump-config"}), LocalizeApp::Action::DumpConfig);
    return app.dumpConfig();
}

/// Every key of an INI text and its value (comments stripped).
std::map<Key, std::string> keysOf(const std::string& text) {
    const mrpt::config::CConfigFileMemory c(text);
    std::vector<std::string> sections;
    c.getAllSections(sections);
    std::map<Key, std::string> out;
    for (const auto& s : sections) {
        std::vector<std::string> keys;
        c.getAllKeys(s, keys);
        for (const auto& k : keys)
            out[{s, superloc::stripIniValue(k)}] = superloc::stripIniValue(c.read_string(s, k, ""));
    }
    return out;
}

/// The same value as printed by --dump-config ("0.100000", "1.000000e-04", "true", "") and as
/// written in the page ("0.1", "0.0001", "true", "(empty)").
bool sameValue(const std::string& dumped, const std::string& page) {
    if (page == "(empty)") return dumped.empty();
    double a, b;
    if (superloc::parseDouble(dumped, a) && superloc::parseDouble(page, b))
        return std::abs(a - b) <= 1e-6 * std::max(1.0, std::abs(a));
    return dumped == page;
}

}  // namespace

TEST(UserConfig, LocalizeIniHoldsAtMostFortyKnownKeysEachAtItsDefault) {
    const std::string ini = superloc::testing::sourcePath("ini/localize.ini");
    const auto user = keysOf(readText(ini));
    EXPECT_GE(user.size(), 20u);
    EXPECT_LE(user.size(), 40u) << "ini/localize.ini holds what a user tunes; list the rest in doc/parameters.md";
    const std::string dump = dumpOf(ini);
    const auto all = keysOf(dump);
    for (const auto& [k, v] : user) EXPECT_TRUE(all.count(k)) << "[" << k.first << "] " << k.second;
    // The effective configuration is the code's defaults: a key set in ini/localize.ini to
    // another value would make every INI that omits it (ini/localize-kitti.ini, a user's own)
    // run differently. Change the default in code instead.
    const std::string empty = superloc::testing::freshDir("user_config") + "/empty.ini";
    std::ofstream(empty) << "[run]\n";
    const auto defaults = keysOf(dumpOf(empty));
    ASSERT_EQ(all.size(), defaults.size());
    for (const auto& [k, v] : user)
        EXPECT_EQ(all.at(k), defaults.at(k)) << "[" << k.first << "] " << k.second << " is not its code default";
    EXPECT_EQ(dump, dumpOf(empty));
}

TEST(UserConfig, ParametersPageListsEveryKeyOnceWithItsDefault) {
    const auto all = keysOf(dumpOf(superloc::testing::sourcePath("ini/localize.ini")));
    const auto user = keysOf(readText(superloc::testing::sourcePath("ini/localize.ini")));
    // Rows: | `[section]` | `key` | default | unit | meaning | read by | yes or empty |
    // (split on '|' by hand: std::regex trips GCC 12's -Wmaybe-uninitialized under the sanitizers)
    const auto trim = [](std::string t) {
        t.erase(0, t.find_first_not_of(' '));
        t.erase(t.find_last_not_of(' ') + 1);
        return t;
    };
    const auto unquote = [](const std::string& t, const std::string& open, const std::string& close) {
        return t.size() >= open.size() + close.size() && t.compare(0, open.size(), open) == 0 &&
                       t.compare(t.size() - close.size(), close.size(), close) == 0
                   ? t.substr(open.size(), t.size() - open.size() - close.size())
                   : std::string();
    };
    std::map<Key, int> seen;
    std::istringstream page(readText(superloc::testing::sourcePath("doc/parameters.md")));
    std::string line;
    while (std::getline(page, line)) {
        if (line.rfind("| `[", 0) != 0 || line.back() != '|') continue;
        std::vector<std::string> cells;
        for (size_t a = 1, b; (b = line.find('|', a)) != std::string::npos; a = b + 1)
            cells.push_back(trim(line.substr(a, b - a)));
        if (cells.size() < 7) continue;
        const Key k{unquote(cells[0], "`[", "]`"), unquote(cells[1], "`", "`")};
        if (k.first.empty() || k.second.empty()) continue;
        const std::string def = cells[2];
        const bool in_user_ini = cells.back() == "yes";
        ++seen[k];
        const auto it = all.find(k);
        if (it == all.end()) {
            ADD_FAILURE() << "doc/parameters.md lists [" << k.first << "] " << k.second
                          << ", which --dump-config does not print";
            continue;
        }
        EXPECT_TRUE(sameValue(it->second, def))
            << "[" << k.first << "] " << k.second << ": the page says " << def << ", the code " << it->second;
        EXPECT_EQ(in_user_ini, user.count(k) == 1) << "[" << k.first << "] " << k.second << ": 'in ini/localize.ini'";
    }
    for (const auto& [k, v] : all)
        EXPECT_EQ(seen[k], 1) << "doc/parameters.md must list [" << k.first << "] " << k.second << " once";
}

TEST(UserConfig, ARemovedKeyIsAOneLineErrorNamingIt) {
    // [global_search] ambiguity_ratio flagged a search result no module read; an INI written
    // before it was removed is rejected like any unknown key.
    const std::string ini = superloc::testing::freshDir("user_config_removed") + "/old.ini";
    std::ofstream(ini) << "[global_search]\nresolution = 0.25\nambiguity_ratio = 0.9\n";
    LocalizeApp app;
    const std::string err = superloc::testing::errorOf([&] { app.initialize(std::vector<std::string>{ini, "--dump-config"}); });
    EXPECT_NE(err.find("unknown key 'ambiguity_ratio' in section [global_search]"), std::string::npos) << err;
    EXPECT_NE(err.find(ini), std::string::npos) << err;
    EXPECT_EQ(err.find('\n'), std::string::npos) << err;
}
