// superloc-sim: synthetic LiDAR + IMU + odom_alt sequences in degenerate worlds (doc/sim.md).
#include <superloc/core/errors.h>
#include <mrpt/system/progress.h>
#include <superloc/app/sim_app.h>
#include <unistd.h>

#include <iostream>

int main(int argc, char** argv) {
    try {
        superloc::app::SimApp app;
        if (!app.initialize(argc, argv)) {
            std::cout << superloc::app::SimApp::usage();
            return 0;
        }
        if (app.dumpConfig()) {
            std::cout << superloc::sim::effectiveConfig(app.config());
            return 0;
        }
        if (isatty(STDERR_FILENO))
            app.on_progress = [](double f) {
                std::cerr << "\r" << mrpt::system::progress(f, 40) << ' '
                          << static_cast<int>(100 * f) << " %" << (f >= 1.0 ? "\n" : "")
                          << std::flush;
            };
        app.run();
        return 0;
    } catch (const std::exception& e) {
        std::cerr << "superloc-sim: " << superloc::oneLineError(e) << "\n";
        return 1;
    }
}
