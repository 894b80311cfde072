#include <superloc/app/ini_sections.h>

namespace superloc::app {
namespace {

// Every section of superloc-localize (localization::LocalizerParams::load reads the Localizer's).
const std::vector<std::string> kLocalize = {"run",    "localization",   "association",    "features",     "fusion",
                                            "imu",    "risk",           "health",       "relocalization",
                                            "global_search", "rawlog",  "map"};

// The sections of the INI files superloc-localize, -map, -import and -eval read.
std::vector<std::string> shared() {
    std::vector<std::string> s = kLocalize;
    s.insert(s.end(), {"rosbag", "eval"});
    return s;
}

}  // namespace

const IniSections& localizeSections() {
    static const IniSections s{"superloc-localize", kLocalize, shared(), {}};
    return s;
}

const IniSections& mapSections() {
    static const IniSections s{"superloc-map", {"rawlog"}, shared(), {}};
    return s;
}

const IniSections& importSections() {
    static const IniSections s{"superloc-import", {"rosbag"}, shared(), {}};
    return s;
}

const IniSections& evalSections() {
    static const IniSections s{"superloc-eval", {"eval"}, shared(), {}};
    return s;
}

const IniSections& suiteSections() {
    static const IniSections s{"superloc-bench", {"suite", "eval"}, {}, {"seq."}};
    return s;
}

}  // namespace superloc::app
