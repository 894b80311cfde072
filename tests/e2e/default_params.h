// The default INI of the e2e tests that drive a Localizer directly.
#pragma once

#include <mrpt/config/CConfigFileMemory.h>
#include <superloc/localization/localizer.h>
#include <superloc_testing/testing.h>

#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace superloc::testing {

/// The default INI (ini/localize.ini) with `sets` ("section.key=value") applied; the file is
/// never written back.
inline localization::LocalizerParams defaultParams(const std::vector<std::string>& sets) {
    std::ifstream f(sourcePath("ini/localize.ini"));
    std::stringstream text;
    text << f.rdbuf();
    mrpt::config::CConfigFileMemory ini(text.str());
    for (const auto& s : sets) {
        const auto dot = s.find('.'), eq = s.find('=');
        ini.write(s.substr(0, dot), s.substr(dot + 1, eq - dot - 1), s.substr(eq + 1));
    }
    return localization::LocalizerParams::load(ini, "ini/localize.ini");
}

}  // namespace superloc::testing
