// superloc-sim: synthetic LiDAR + IMU + odom_alt sequences in degenerate worlds (DESIGN §7, §9).
#include <mrpt/core/exceptions.h>
#include <mrpt/system/progress.h>
#include <superloc/sim/sim_app.h>
#include <unistd.h>

#include <iostream>
#include <sstream>

int main(int argc, char** argv) {
    try {
        superloc::sim::SimApp app;
        if (!app.initialize(argc, argv)) {
            std::cout << superloc::sim::SimApp::usage();
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
        // One line: the first line of the message that is not an MRPT banner or call stack.
        std::istringstream lines(mrpt::exception_to_str(e));
        std::string line, msg;
        while (std::getline(lines, line))
            if (!line.empty() && line.rfind("====", 0) != 0) {
                msg = line;
                break;
            }
        std::cerr << "superloc-sim: " << (msg.empty() ? std::string(e.what()) : msg) << "\n";
        return 1;
    }
}
