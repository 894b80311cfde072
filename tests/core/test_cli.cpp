#include <gtest/gtest.h>
#include <superloc/core/cli.h>
#include <superloc/core/config.h>

using namespace superloc;

TEST(FlagValue, TakesTheNextArgumentAndAdvances) {
    const std::vector<std::string> args = {"--out", "dir", "--quiet"};
    size_t i = 0;
    EXPECT_EQ(flagValue(args, i), "dir");
    EXPECT_EQ(i, 1u);
}

TEST(FlagValue, LastFlagIsAOneLineErrorNamingIt) {
    const std::vector<std::string> args = {"--rawlog", "a", "--map"};
    size_t i = 2;
    try {
        flagValue(args, i);
        FAIL() << "no error";
    } catch (const ConfigError& e) {
        EXPECT_STREQ(e.what(), "--map: missing value (see --help)");
    }
    char a0[] = "app", a1[] = "--seed";
    char* argv[] = {a0, a1};
    int j = 1;
    EXPECT_THROW(flagValue(2, argv, j), ConfigError);
}
