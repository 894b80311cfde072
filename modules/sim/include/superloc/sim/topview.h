// A small SVG writer: top view of a world (walls dark, floors light, rasterised on a grid) with
// the trajectory coloured by height, a start/end marker and a scale bar.
#pragma once

#include <superloc/core/types.h>
#include <superloc/sim/mesh.h>

#include <string>
#include <vector>

namespace superloc::sim {

struct TopViewOptions {
    double cell = 0.25;     ///< [m] raster cell
    double margin = 40.0;   ///< [m] shown around the trajectory's bounding box
    int max_pixels = 1100;  ///< longest image side [px]
    std::string title;
};

/// The SVG document as text (the caller writes it to a file).
std::string topViewSvg(const Mesh& mesh, const std::vector<Vec3d>& trajectory,
                       const TopViewOptions& opt);

}  // namespace superloc::sim
