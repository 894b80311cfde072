// PointGrid: bounded nearest / k-nearest queries against a brute-force search.
#include <gtest/gtest.h>
#include <superloc/map/point_grid.h>

#include <algorithm>
#include <random>

using namespace superloc;
using superloc::map::PointGrid;

namespace {
std::vector<Vec3f> randomPoints(size_t n, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> U(-3.0f, 3.0f);
    std::vector<Vec3f> p(n);
    for (auto& x : p) x = Vec3f(U(rng), U(rng), 0.5f * U(rng));
    return p;
}
}  // namespace

TEST(PointGrid, NearestWithinTwoCellsIsTheBruteForceNearest) {
    const std::vector<Vec3f> pts = randomPoints(3000, 1);
    const PointGrid grid(pts, 0.5);
    EXPECT_GT(grid.cells(), 100u);
    std::mt19937 rng(2);
    std::uniform_real_distribution<float> U(-4.5f, 4.5f);
    int found = 0, none = 0;
    for (int q = 0; q < 2000; ++q) {
        const Vec3f x(U(rng), U(rng), U(rng));
        float best_d2 = 1e30f;
        for (const Vec3f& p : pts) best_d2 = std::min(best_d2, (p - x).squaredNorm());
        for (const float r : {0.5f, 0.3f, 0.8f, 1.0f}) {
            const auto [j, d2] = grid.nearest(x, r);
            if (best_d2 <= r * r) {
                ASSERT_NE(j, PointGrid::kNone) << x.transpose();
                EXPECT_FLOAT_EQ(d2, best_d2);
                EXPECT_FLOAT_EQ((pts[j] - x).squaredNorm(), best_d2);
                ++found;
            } else {
                EXPECT_EQ(j, PointGrid::kNone) << "beyond the bound: none";
                ++none;
            }
        }
        // A radius beyond two cells is clamped to them: never a point farther than 1 m.
        const auto [j, d2] = grid.nearest(x, 5.0f);
        if (best_d2 > 1.0f) EXPECT_EQ(j, PointGrid::kNone);
        else EXPECT_FLOAT_EQ(d2, best_d2);
    }
    EXPECT_GT(found, 500);
    EXPECT_GT(none, 100);
}

TEST(PointGrid, AHintBoundsTheSearchWithoutChangingTheAnswer) {
    // Any point as a hint (the last round's nearest, a far one, one beyond the radius, none)
    // gives the answer the search gives without it.
    const std::vector<Vec3f> pts = randomPoints(3000, 5);
    const PointGrid grid(pts, 0.5);
    std::mt19937 rng(6);
    std::uniform_real_distribution<float> U(-4.5f, 4.5f), J(-0.05f, 0.05f);
    std::uniform_int_distribution<uint32_t> any(0, static_cast<uint32_t>(pts.size() - 1));
    int hinted = 0;
    for (int q = 0; q < 2000; ++q) {
        const Vec3f x(U(rng), U(rng), U(rng));
        for (const float r : {0.3f, 1.0f}) {
            const auto plain = grid.nearest(x, r);
            const Vec3f moved = x + Vec3f(J(rng), J(rng), J(rng));  // the feature a round later
            const auto before = grid.nearest(moved, r);
            for (const uint32_t hint : {before.first, any(rng), PointGrid::kNone, static_cast<uint32_t>(pts.size() + 7)}) {
                const auto h = grid.nearest(x, r, hint);
                EXPECT_EQ(h.first, plain.first) << "hint " << hint;
                if (plain.first != PointGrid::kNone) {
                    EXPECT_FLOAT_EQ(h.second, plain.second);
                }
                hinted += hint != PointGrid::kNone;
            }
        }
    }
    EXPECT_GT(hinted, 4000);
}

TEST(PointGrid, TheSecondBoundIsBelowEveryOtherPointAndKeepsTheAnswerWithinHalfTheGap) {
    // `second` bounds from below the distance of every point but the nearest within the radius
    // (brute force), often tightly; a query moved by less than half the gap between the two has
    // the same nearest point (what the association's memo relies on).
    const std::vector<Vec3f> pts = randomPoints(3000, 11);
    const PointGrid grid(pts, 0.5);
    std::mt19937 rng(12);
    std::uniform_real_distribution<float> U(-3.5f, 3.5f), D(-1.0f, 1.0f);
    int checked = 0, tight = 0, moved = 0;
    for (int q = 0; q < 2000; ++q) {
        const Vec3f x(U(rng), U(rng), 0.5f * U(rng));
        for (const float r : {0.3f, 1.0f}) {
            float second = -1;
            const auto [j, d2] = grid.nearest(x, r, PointGrid::kNone, &second);
            if (j == PointGrid::kNone) continue;
            float other = r * r;  // the true second nearest within the radius
            for (uint32_t i = 0; i < pts.size(); ++i)
                if (i != j) other = std::min(other, (pts[i] - x).squaredNorm());
            ASSERT_LE(second, other) << x.transpose();
            ASSERT_GE(second, d2);
            tight += second >= 0.99f * other;
            ++checked;
            // Any move of less than half the gap: the same nearest point.
            const float gap = std::sqrt(second) - std::sqrt(d2);
            if (!(gap > 1e-4f)) continue;
            Vec3f dir(D(rng), D(rng), D(rng));
            dir.normalize();
            const Vec3f y = x + (0.499f * gap) * dir;
            EXPECT_EQ(grid.nearest(y, r).first, j) << x.transpose();
            ++moved;
        }
    }
    EXPECT_GT(checked, 2000);
    EXPECT_GT(moved, 1500);
    EXPECT_GT(tight, checked / 4) << "the bound is often the true second nearest";
}

TEST(PointGrid, KnnIsTheBruteForceKnnWithinTheRadius) {
    const std::vector<Vec3f> pts = randomPoints(3000, 3);
    const PointGrid grid(pts, 0.5);
    std::mt19937 rng(4);
    std::uniform_real_distribution<float> U(-3.0f, 3.0f);
    std::vector<uint32_t> idx;
    std::vector<float> d2;
    for (int q = 0; q < 300; ++q) {
        const Vec3f x(U(rng), U(rng), 0.5f * U(rng));
        for (const float r : {0.5f, 0.9f}) {
            std::vector<float> all;
            for (const auto& p : pts)
                if ((p - x).squaredNorm() <= r * r) all.push_back((p - x).squaredNorm());
            std::sort(all.begin(), all.end());
            grid.knn(x, 6, r, idx, d2);
            ASSERT_EQ(idx.size(), std::min<size_t>(6, all.size()));
            for (size_t k = 0; k < idx.size(); ++k) {
                EXPECT_FLOAT_EQ(d2[k], all[k]);
                EXPECT_FLOAT_EQ((pts[idx[k]] - x).squaredNorm(), d2[k]);
            }
        }
    }
}

TEST(PointGrid, EmptyAndBadInput) {
    const std::vector<Vec3f> none, single = {Vec3f(1, 1, 1)};  // a grid reads its points in place
    const PointGrid empty(none, 0.5);
    EXPECT_EQ(empty.nearest(Vec3f::Zero(), 0.5f).first, PointGrid::kNone);
    EXPECT_THROW(PointGrid(none, 0.0), std::invalid_argument);
    const PointGrid one(single, 0.5);
    EXPECT_EQ(one.nearest(Vec3f(1.1f, 1, 1), 0.5f).first, 0u);
    EXPECT_EQ(one.nearest(Vec3f(std::nanf(""), 1, 1), 0.5f).first, PointGrid::kNone);
    EXPECT_EQ(one.nearest(Vec3f(1e9f, 1, 1), 0.5f).first, PointGrid::kNone);  // beyond the key range
}
