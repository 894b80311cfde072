// libFuzzer target: superloc-localize's configuration path — an INI file plus --set overrides,
// validated and loaded into every module's Params (LocalizeApp::initialize with --dump-config,
// which stops after loading), then printed back (dumpConfig).
// Input: lines starting with "--set " are overrides (the rest of the line is the assignment);
// every other line is the INI text.
#include <superloc/app/localize_app.h>

#include <string>
#include <vector>

#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string input(reinterpret_cast<const char*>(data), size);
    std::string ini;
    std::vector<std::string> args;
    const std::string& path = superloc::fuzz::scratchPath(".ini");
    args.push_back(path);
    size_t pos = 0;
    while (pos < input.size()) {
        size_t end = input.find('\n', pos);
        if (end == std::string::npos) end = input.size();
        const std::string line = input.substr(pos, end - pos);
        if (line.rfind("--set ", 0) == 0) {
            args.push_back("--set");
            args.push_back(line.substr(6));
        } else {
            ini += line + '\n';
        }
        pos = end + 1;
    }
    args.push_back("--dump-config");
    args.push_back("--quiet");
    superloc::fuzz::writeBytes(path, reinterpret_cast<const uint8_t*>(ini.data()), ini.size());
    superloc::fuzz::expectLoadsOrThrowsOneLine([&] {
        superloc::app::LocalizeApp app;
        if (app.initialize(args) != superloc::app::LocalizeApp::Action::DumpConfig)
            std::abort();  // --dump-config always stops after loading
        const std::string dumped = app.dumpConfig();
        if (dumped.find("[localization]") == std::string::npos) std::abort();
    });
    return 0;
}
