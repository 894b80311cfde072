// superloc-localize: map-based LiDAR-inertial localization of a rawlog (doc/localizer.md).
#include <superloc/core/errors.h>
#include <mrpt/system/os.h>
#include <superloc/app/localize_app.h>
#include <unistd.h>

#include <cstdio>
#include <iostream>

int main(int argc, char** argv) {
    using superloc::app::LocalizeApp;
    try {
        LocalizeApp app;
        switch (app.initialize(argc, argv)) {
            case LocalizeApp::Action::Help: std::cout << LocalizeApp::usage(); return 0;
            case LocalizeApp::Action::DumpConfig: std::cout << app.dumpConfig(); return 0;
            case LocalizeApp::Action::Run: break;
        }
        const bool bar = !app.quiet() && isatty(fileno(stderr));
        const int rc = app.run([bar](const superloc::localization::FrameReport& r) {
            if (bar)
                std::fprintf(stderr, "\rframe %6zu  t=%.2f  %6.2f ms  inliers %3.0f%%%s   ", r.index, r.t,
                             r.ms.total, 100 * r.inlier_ratio, r.diverged ? "  DIVERGED" : "");
        });
        if (bar) std::fprintf(stderr, "\n");
        return rc;
    } catch (const std::exception& e) {
        std::cerr << "superloc-localize: error: " << superloc::oneLineError(e) << "\n";
        return 1;
    }
}
