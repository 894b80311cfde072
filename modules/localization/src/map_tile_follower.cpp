// MapTileFollower: the tiles around the robot, prepared in a thread and swapped in by pose.
#include <mrpt/system/CTicTac.h>
#include <superloc/localization/map_tile_follower.h>

#include <algorithm>

namespace superloc::localization {

MapTileFollower::MapTileFollower(const std::string& dir, const map::MapParams& map, const LocalizerParams& params)
    : tiles_(dir, map, map.tile_radius), map_params_(map), params_(params) {}

MapTileFollower::~MapTileFollower() {
    if (next_.valid()) next_.wait();
}

std::shared_ptr<const map::PriorMap> MapTileFollower::start(const Vec3d& p) {
    auto m = tiles_.loadAround(p);
    center_ = p;
    stats_.points_max = std::max(stats_.points_max, m->size());
    return m;
}

bool MapTileFollower::update(const Vec3d& p, Localizer& loc) {
    const double d = (p - center_).head<2>().norm();
    if (!next_.valid() && d > 0.5 * map_params_.tile_reload) {
        // The thread reads tiles_ and the copied parameters only; nothing else touches tiles_
        // until get().
        next_ = std::async(std::launch::async, [this, p, params = params_] {
            auto m = tiles_.loadAround(p);
            if (m->size() == 0) return PreparedMap{};
            return Localizer::prepareMap(params, std::move(m));
        });
    }
    if (!next_.valid() || d <= map_params_.tile_reload) return false;
    mrpt::system::CTicTac wait;
    PreparedMap next = next_.get();
    center_ = tiles_.center();
    if (!next.map) return false;  // no tile there: keep the map in use (tried again further on)
    const size_t points = next.map->size();
    loc.setMap(std::move(next));
    stats_.reloads++;
    stats_.points_max = std::max(stats_.points_max, points);
    stats_.load_s_max = std::max(stats_.load_s_max, tiles_.lastLoadSeconds());
    stats_.wait_s_max = std::max(stats_.wait_s_max, wait.Tac());
    return true;
}

}  // namespace superloc::localization
