// NearestCells: the memoized nearest answers against the kd-tree's, their independence of the
// cache's state, and its bound on memory.
#include <superloc/map/nearest_cells.h>
#include <superloc/map/prior_map.h>
#include <superloc_testing/testing.h>

#include <cmath>
#include <random>

using namespace superloc;
using namespace superloc::map;

namespace {
/// A room-like map: a floor and two walls meeting at a corner, points every 10 cm with 1 cm of
/// noise, and a box on the floor; voxel-filtered at 0.1 m as a prior map is.
PriorMap roomMap() {
    std::mt19937 rng(3);
    std::normal_distribution<float> g(0.f, 0.01f);
    PointCloud c;
    for (int i = 0; i < 100; ++i)
        for (int j = 0; j < 100; ++j) {
            const float a = i * 0.1f, b = j * 0.1f;
            c.points.emplace_back(a, b, g(rng));          // floor z = 0
            if (j < 30) c.points.emplace_back(a, g(rng), b * 1.0f);  // wall y = 0, 3 m high
            if (i < 30) c.points.emplace_back(g(rng), b, a * 1.0f);  // wall x = 0
        }
    for (int i = 0; i < 10; ++i)
        for (int j = 0; j < 10; ++j) c.points.emplace_back(5.f + i * 0.1f, 5.f + j * 0.1f, 0.5f);  // box top
    MapParams p;
    p.voxel_size = 0.1;
    return PriorMap(c, p);
}

/// Queries near the surfaces (within 0.3 m), as a tracked frame's features are.
std::vector<Vec3f> queries(size_t n, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.f, 9.9f), off(-0.3f, 0.3f);
    std::vector<Vec3f> q;
    for (size_t i = 0; i < n; ++i) {
        switch (i % 3) {
            case 0: q.emplace_back(u(rng), u(rng), off(rng)); break;
            case 1: q.emplace_back(u(rng), off(rng), u(rng) * 0.3f); break;
            default: q.emplace_back(off(rng), u(rng), u(rng) * 0.3f); break;
        }
    }
    return q;
}
}  // namespace

TEST(NearestCells, AnswersAsTheKdTreeDoesWithinTheCellsReach) {
    const PriorMap map = roomMap();
    for (const double edge : {0.1, 0.2, 0.3}) {
        NearestCells cells(edge);
        size_t same = 0;
        double worst_excess = 0;
        const auto q = queries(20000, 11);
        for (const Vec3f& x : q) {
            const auto [j, d2] = cells.nearest(map, x);
            const auto [jt, d2t] = map.nearest(x);
            ASSERT_LT(j, map.size());
            EXPECT_NEAR(d2, (map.point(j) - x).squaredNorm(), 1e-5);
            if (j == jt) ++same;
            worst_excess = std::max(worst_excess, std::sqrt(double(d2)) - std::sqrt(double(d2t)));
        }
        // At 0.1 m cells on a 0.1 m map the four candidates nearly always hold the nearest point;
        // coarser cells miss it more often, never by more than the cell's diagonal.
        const double share = double(same) / double(q.size());
        SCOPED_TRACE(edge);
        EXPECT_GT(share, edge < 0.15 ? 0.9 : edge < 0.25 ? 0.6 : 0.4);
        EXPECT_LE(worst_excess, edge * std::sqrt(3.0) + 1e-6);
        EXPECT_LT(cells.misses(), cells.queries());
    }
}

TEST(NearestCells, AnswerDoesNotDependOnTheCachesState) {
    const PriorMap map = roomMap();
    const auto q = queries(5000, 5);
    NearestCells warm(0.2), bounded(0.2, 64);
    // `warm` sees the queries twice (its second pass all hits); `bounded` is emptied every 64
    // cells. Both give the answers of a fresh memo per query.
    for (const Vec3f& x : q) warm.nearest(map, x);
    for (const Vec3f& x : q) {
        NearestCells fresh(0.2);
        const auto a = fresh.nearest(map, x);
        EXPECT_EQ(warm.nearest(map, x), a);
        EXPECT_EQ(bounded.nearest(map, x), a);
    }
    EXPECT_LE(bounded.cells(), 64u);
    EXPECT_GT(warm.cells(), 64u);
}

TEST(NearestCells, RejectsBadInput) {
    EXPECT_THROW(NearestCells(0.0), std::invalid_argument);
    EXPECT_THROW(NearestCells(std::nan("")), std::invalid_argument);
    const PriorMap map = roomMap();
    NearestCells cells(0.2);
    EXPECT_EQ(cells.nearest(map, Vec3f(NAN, 0, 0)).first, std::numeric_limits<uint32_t>::max());
    EXPECT_EQ(cells.nearest(map, Vec3f(1e9f, 0, 0)).first, std::numeric_limits<uint32_t>::max());
    const PriorMap empty(PointCloud{}, MapParams{});
    EXPECT_EQ(cells.nearest(empty, Vec3f(0, 0, 0)).first, std::numeric_limits<uint32_t>::max());
}

TEST(NearestCells, PriorMapKeepsOneMemoPerEdge) {
    const PriorMap map = roomMap();
    NearestCells* a = map.nearestCells(0.2).second;
    NearestCells* b = map.nearestCells(0.2).second;
    NearestCells* c = map.nearestCells(0.1).second;
    EXPECT_EQ(a, b);
    EXPECT_NE(a, c);
    const size_t before = map.memoryBytes();
    a->nearest(map, Vec3f(1, 1, 0.1f));
    EXPECT_GE(map.memoryBytes(), before);
}
