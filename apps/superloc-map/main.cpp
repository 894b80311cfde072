// superloc-map: prior map from a rawlog's scans and their poses. See superloc::app::MapApp.
#include <mrpt/system/progress.h>
#include <superloc/core/errors.h>
#include <superloc/app/command_line.h>
#include <superloc/app/map_app.h>
#include <unistd.h>

#include <cstdio>
#include <iostream>

int main(int argc, char** argv) {
    try {
        const auto args = superloc::app::parseMapAppArgs(superloc::app::argList(argc, argv));
        if (args.help) {
            std::cout << superloc::app::mapAppUsage();
            return 0;
        }
        superloc::app::MapApp app(args);
        superloc::io::ProgressFn bar;
        if (isatty(fileno(stderr)))
            bar = [](size_t done, size_t total) {
                std::cerr << "\r" << mrpt::system::progress(total ? double(done) / total : 1.0, 40)
                          << " " << done << "/" << total << " scans" << std::flush;
            };
        app.run(bar);
        if (bar) std::cerr << "\n";
        const auto& r = app.result();
        std::cout << args.out << ": " << r.map_points << " map points";
        if (args.from_map.empty()) {
            std::cout << " from " << r.scans_used << " scans (" << r.points_in << " points in";
            if (r.scans_without_pose) std::cout << ", " << r.scans_without_pose << " scans without pose skipped";
            std::cout << ")";
        } else {
            std::cout << " from " << args.from_map;
        }
        if (app.tilesWritten()) std::cout << " in " << app.tilesWritten() << " tiles of " << args.tile_size << " m";
        std::cout << "\n";
        if (const auto& s = app.stats())
            std::cout << "median point-to-plane fit residual: " << s->median_fit_residual * 1000
                      << " mm (all points), " << s->median_planar_fit_residual * 1000
                      << " mm (planar points, " << s->planar_fraction * 100 << "% of the map); "
                      << "normals of " << s->points << " points in " << s->prepare_seconds << " s\n";
        return 0;
    } catch (const std::exception& e) {
        std::cerr << "superloc-map: " << superloc::oneLineError(e) << "\n";
        return 1;
    }
}
