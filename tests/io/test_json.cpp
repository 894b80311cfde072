// JSON files through nlohmann::json: non-finite numbers become null (and are reported), the text
// parses back with a standard parser, errors name the file.
#include <nlohmann/json.hpp>
#include <superloc/io/json_file.h>
#include <superloc_testing/testing.h>

#include <cmath>
#include <fstream>
#include <limits>

using namespace superloc;

TEST(Json, NonFiniteNumbersBecomeNullAndAreReported) {
    const double inf = std::numeric_limits<double>::infinity();
    io::Json j = {{"ok", 1.5},
                  {"inf", inf},
                  {"nested", {{"nan", std::nan("")}, {"list", {1.0, -inf, 2.0}}}},
                  {"count", 3}};
    // A 1e300 m pose squared overflows: the ATE of such a run is inf.
    volatile double far = 1e300;
    j["ate"] = std::sqrt(far * far);
    const auto replaced = io::replaceNonFinite(j);
    EXPECT_EQ(replaced,
              (std::vector<std::string>{"/inf", "/nested/nan", "/nested/list/1", "/ate"}));
    EXPECT_TRUE(j["inf"].is_null());
    EXPECT_TRUE(j["nested"]["list"][1].is_null());
    EXPECT_DOUBLE_EQ(j["nested"]["list"][2].get<double>(), 2.0);
    EXPECT_EQ(j["count"].get<int>(), 3);
}

TEST(Json, TextParsesWithAStandardParserInInsertionOrder) {
    io::Json j;
    j["method"] = "superloc";
    j["frames"] = 16;
    j["ms"] = std::numeric_limits<double>::quiet_NaN();
    j["path"] = "a \"quoted\"\nname";
    const std::string text = io::toJsonText(j, "test");
    EXPECT_EQ(text.find("nan"), std::string::npos) << text;
    EXPECT_LT(text.find("\"method\""), text.find("\"frames\"")) << text;
    const auto back = nlohmann::json::parse(text);
    EXPECT_EQ(back["method"], "superloc");
    EXPECT_EQ(back["frames"].get<int>(), 16);
    EXPECT_TRUE(back["ms"].is_null());
    EXPECT_EQ(back["path"], "a \"quoted\"\nname");
}

TEST(Json, SaveAndLoadRoundTripWithTolerance) {
    const std::string dir = superloc::testing::freshDir("io_json");
    volatile double far = 1e300;
    io::Json j = {{"rmse", 0.1 + 0.2}, {"big", 1e300}, {"tiny", 1e-300}, {"inf", far * far}};
    io::saveJson(dir + "/a.json", j);
    const io::Json back = io::loadJson(dir + "/a.json");
    EXPECT_NEAR(back["rmse"].get<double>(), 0.3, 1e-12);
    EXPECT_NEAR(back["big"].get<double>() / 1e300, 1.0, 1e-12);
    EXPECT_NEAR(back["tiny"].get<double>() / 1e-300, 1.0, 1e-12);
    EXPECT_TRUE(back["inf"].is_null());
}

TEST(Json, ErrorsAreOneLineAndNameTheFile) {
    const std::string dir = superloc::testing::freshDir("io_json_errors");
    std::ofstream(dir + "/bad.json") << "{\"a\": 1,\n \"b\": inf}\n";
    for (const std::string& f : {dir + "/bad.json", dir + "/missing.json"}) {
        try {
            io::loadJson(f);
            ADD_FAILURE() << f;
        } catch (const std::runtime_error& e) {
            const std::string msg = e.what();
            EXPECT_NE(msg.find(f), std::string::npos) << msg;
            EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
        }
    }
    EXPECT_THROW(io::saveJson(dir + "/no/such/dir/x.json", io::Json::object()), std::runtime_error);
}
