#include <superloc/core/se3.h>
#include <superloc/fusion/odom_calibration.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace superloc::fusion {

namespace {
/// Ridge on the fit (in the units of sum a a^T): a weak pull of b, s, c towards zero that keeps
/// an axis defined before it has seen motion (a straight drive says nothing of a rotation scale).
constexpr double kRidgeSlope = 1e-3;   ///< on the motion term: b [m^2], s [rad^2]
constexpr double kRidgePerM = 1e-1;    ///< on the per-metre rotation term c [m^2]


Eigen::Vector2d regressor(int k, double d, double motion_k) {
    return k < 3 ? Eigen::Vector2d(d, 0.0) : Eigen::Vector2d(motion_k, d);
}
}  // namespace

void OdomCalibration::solve(Axis& a, bool rotation) const {
    Eigen::Matrix2d A = a.A;
    A(0, 0) += rotation ? kRidgeSlope : kRidgeSlope;
    A(1, 1) += rotation ? kRidgePerM : 1.0;  // translation: the second entry is unused
    const Eigen::LDLT<Eigen::Matrix2d> ldlt(A);
    a.x = ldlt.solve(a.g);
    if (!rotation) a.x[1] = 0;
    a.cov = ldlt.solve(Eigen::Matrix2d::Identity());
    const double ssr = std::max(0.0, a.rr - 2.0 * a.x.dot(a.g) + a.x.dot(a.A * a.x));
    const double dof = a.n - (rotation ? 2.0 : 1.0);
    a.var = dof > 1.0 ? ssr / dof : 0.0;
}

void OdomCalibration::fitWorth(Axis& a) const {
    // Per block length: the share k of the correction that predicted best out of sample,
    // k = sum(e c) / sum(c^2) clamped to [0, 1] (e: the raw error over a block, c: what the fit
    // of the block's start predicted), with one pseudo-block in which the correction was right
    // (k = 1 until the blocks say otherwise). Then what that shrunk correction left,
    // e2 = sum (e - k c)^2, by block length.
    std::array<double, 7> e2{};
    for (size_t h = 0; h < a.blocks.size(); ++h) {
        a.shrink[h] = 1.0;
        if (a.cnt[h] < p_.min_blocks - 1e-9 || !(a.len[h] > 0)) continue;
        if (a.cc[h] > 0) {
            const double prior = a.cc[h] / a.cnt[h];
            a.shrink[h] = std::clamp((a.ec[h] + prior) / (a.cc[h] + prior), 0.0, 1.0);
        }
        const double k = a.shrink[h];
        e2[h] = std::max(0.0, a.ee[h] - 2.0 * k * a.ec[h] + k * k * a.cc[h]);
    }
    // Weighted least squares of q = V / L = wa + wb L over the block lengths with enough blocks,
    // weights n / q^2 (each mean squared error is known to a relative precision ~ 1 / sqrt(n)).
    double s00 = 0, s01 = 0, s11 = 0, r0 = 0, r1 = 0;
    int used = 0;
    for (size_t h = 0; h < a.blocks.size(); ++h) {
        if (a.cnt[h] < p_.min_blocks - 1e-9 || !(a.len[h] > 0)) continue;
        const double L = a.len[h] / a.cnt[h];
        const double q = std::max(1e-18, e2[h] / a.cnt[h] / L);
        const double w = a.cnt[h] / (q * q);
        s00 += w, s01 += w * L, s11 += w * L * L, r0 += w * q, r1 += w * q * L;
        ++used;
    }
    a.worth = used > 0;
    if (!a.worth) return;
    const double det = s00 * s11 - s01 * s01;
    double wa = used > 1 && det > 1e-12 * s00 * s11 ? (s11 * r0 - s01 * r1) / det : -1.0;
    double wb = used > 1 && det > 1e-12 * s00 * s11 ? (s00 * r1 - s01 * r0) / det : -1.0;
    if (used == 1 || wa < 0) {  // one length, or no error that averages out: all of it a drift
        wa = 0;
        wb = r1 / s11;
    } else if (wb < 0) {  // no drift left: an error that averages out
        wb = 0;
        wa = r0 / s00;
    }
    a.wa = wa;
    a.wb = wb;
}

double OdomCalibration::shrinkAt(const Axis& a, double D) const {
    // The blocks of length H measure the correction over 0..H metres after a check; a frame at D
    // metres since the check is nearest to the middle of a block of 2 D.
    double k = 1.0;
    int longest = -1;
    for (size_t h = 0; h < a.blocks.size(); ++h) {
        if (a.cnt[h] < p_.min_blocks - 1e-9) continue;
        k = a.shrink[h];
        longest = int(h);
        if (p_.horizons[h] >= 2.0 * D) return k;
    }
    if (longest < 0 || !a.worth || !(a.cc[longest] > 0) || !(a.len[longest] > 0)) return k;
    // Beyond the longest block measured nothing says the correction still holds. What the blocks
    // do say is how large an error that keeps its sign over them the correction leaves (wb, per
    // metre squared) against the correction's own size over the same blocks (c^2): a fitted
    // correction is the fixed error plus the mean of whatever wandered while it was fitted, and
    // the share of it that is the fixed part is c^2 / (c^2 + wb) (a Wiener / James-Stein shrink,
    // the wander's variance taken as the fit's error). Far beyond the longest block the share
    // tends to that; between, it falls as H / 2D (the measured share over the first H / 2).
    const double H = a.len[longest] / a.cnt[longest];
    const double c2 = a.cc[longest] / a.cnt[longest];  // the correction over a block of H, squared
    const double k_far = c2 / (c2 + a.wb * H * H);
    return k_far + (k - k_far) * H / (2.0 * D);
}

std::array<bool, 6> OdomCalibration::update(const SE3d& odom, const SE3d& est, const std::array<bool, 6>& held) {
    std::array<bool, 6> outlier{};
    const double d = odom.translation().norm();
    if (!std::isfinite(d)) return outlier;
    const Vec3d phi_o = logSO3(odom.linear()), phi_e = logSO3(est.linear());
    const Vec3d t_o = odom.translation(), t_e = est.translation();
    const double forget = std::exp(-d / p_.memory_m);
    for (int k = 0; k < 6; ++k) {
        if (!held[k]) {
            axes_[k].since_m += d;
            continue;
        }
        axes_[k].since_m = 0;
        Axis& a = axes_[k];
        const bool rot = k >= 3;
        const double r = rot ? phi_o[k - 3] - phi_e[k - 3] : t_o[k] - t_e[k];
        const Eigen::Vector2d reg = regressor(k, d, rot ? phi_e[k - 3] : 0.0);
        if (!std::isfinite(r)) continue;
        // A residual far outside what the fit leaves (a jump, a slip it has not seen) is not
        // learned from; tested once the fit has a variance (a few frames).
        if (a.n >= 5 && a.var > 0) {
            const double floor = rot ? p_.sigma_floor_rot : p_.sigma_floor_xyz;
            const double s = std::max(floor, std::sqrt(a.var * (1.0 + reg.dot(a.cov * reg))));
            if (std::abs(r - reg.dot(a.x)) > p_.outlier_sigmas * s) {
                outlier[k] = true;
                ++outliers_[k];
                if (++a.outlier_run < p_.restart_after) continue;
                // The error changed: learn it again, from this frame. What the correction was
                // worth is kept: it just failed, and its blocks say by how much.
                Axis fresh;
                fresh.blocks = a.blocks;
                fresh.ee = a.ee, fresh.ec = a.ec, fresh.cc = a.cc, fresh.len = a.len, fresh.cnt = a.cnt;
                fresh.shrink = a.shrink;
                fresh.wa = a.wa, fresh.wb = a.wb, fresh.worth = a.worth;
                a = fresh;
                ++restarts_[k];
            }
        }
        a.outlier_run = 0;
        // Out of sample first: the blocks are corrected with the fit as it stood when they began.
        // A block begins only where the axis is calibrated (what sigma() is asked for).
        bool closed = false;
        const bool cal = calibrated(k);
        for (size_t h = 0; h < a.blocks.size(); ++h) {
            auto& b = a.blocks[h];
            a.ee[h] *= forget, a.ec[h] *= forget, a.cc[h] *= forget;
            a.len[h] *= forget, a.cnt[h] *= forget;
            if (!b.open && !cal) continue;
            if (!b.open) b = Axis::Block{true, p_.apply_correction ? a.x : Eigen::Vector2d::Zero(), 0.0, 0.0, 0.0};
            b.S += r;
            b.C += reg.dot(b.x0);
            b.L += d;
            if (b.L >= p_.horizons[h]) {
                a.ee[h] += b.S * b.S;
                a.ec[h] += b.S * b.C;
                a.cc[h] += b.C * b.C;
                a.len[h] += b.L;
                a.cnt[h] += 1.0;
                b.open = false;
                closed = true;
            }
        }
        if (closed) fitWorth(a);
        a.A = forget * a.A + reg * reg.transpose();
        a.g = forget * a.g + reg * r;
        a.rr = forget * a.rr + r * r;
        a.n = forget * a.n + 1.0;
        a.held_m += d;
        solve(a, rot);
    }
    return outlier;
}

bool OdomCalibration::calibrated(int k) const { return axes_[k].held_m >= p_.min_held_m && axes_[k].n >= 5; }

SE3d OdomCalibration::correct(const SE3d& odom) const {
    if (!p_.apply_correction) return odom;
    const double d = odom.translation().norm();
    Vec3d t = odom.translation(), phi = logSO3(odom.linear());
    for (int k = 0; k < 3; ++k)
        if (calibrated(k)) t[k] -= shrinkAt(axes_[k], axes_[k].since_m) * axes_[k].x[0] * d;
    for (int k = 0; k < 3; ++k)
        if (calibrated(3 + k)) {
            const auto& a = axes_[3 + k];
            const Eigen::Vector2d x = shrinkAt(a, a.since_m) * a.x;
            phi[k] = (phi[k] - x[1] * d) / std::max(0.1, 1.0 + x[0]);
        }
    SE3d out = SE3d::Identity();
    out.linear() = expSO3(phi);
    out.translation() = t;
    return out;
}

Vec6d OdomCalibration::sigma(const SE3d& odom, Vec6d* worth) const {
    const double d = odom.translation().norm();
    const Vec6d H = measuredHorizon();
    Vec6d s, w;
    for (int k = 0; k < 6; ++k) {
        const Axis& a = axes_[k];
        if (!calibrated(k) || !a.worth) {
            s[k] = w[k] = std::numeric_limits<double>::quiet_NaN();
            continue;
        }
        const double D = a.since_m;
        // V(x) = wa x + wb x^2, the frame's share V(D + d) - V(D).
        const double var = a.wa * d + a.wb * ((D + d) * (D + d) - D * D);
        const double floor = k >= 3 ? p_.sigma_floor_rot : p_.sigma_floor_xyz;
        s[k] = w[k] = std::max(floor, std::sqrt(std::max(0.0, var)));
        if (!(H[k] > 0) || !(D + d > H[k])) continue;
        // The worth beyond H: V(H) (x / H)^3, never below V itself.
        const auto V = [&](double x) {
            const double model = a.wa * x + a.wb * x * x;
            if (x <= H[k]) return model;
            const double r = x / H[k];
            return std::max(model, (a.wa * H[k] + a.wb * H[k] * H[k]) * r * r * r);
        };
        w[k] = std::max(s[k], std::sqrt(std::max(0.0, V(D + d) - V(D))));
    }
    if (worth) *worth = w;
    return s;
}

Vec6d OdomCalibration::measuredHorizon() const {
    Vec6d h = Vec6d::Zero();
    for (int k = 0; k < 6; ++k)
        for (size_t i = 0; i < axes_[k].blocks.size(); ++i)
            if (axes_[k].cnt[i] >= p_.min_blocks - 1e-9 && axes_[k].len[i] > 0) h[k] = p_.horizons[i];
    return h;
}

Vec6d OdomCalibration::shrink() const {
    Vec6d v;
    for (int k = 0; k < 6; ++k) v[k] = shrinkAt(axes_[k], axes_[k].since_m);
    return v;
}

Vec6d OdomCalibration::worthA() const {
    Vec6d v;
    for (int k = 0; k < 6; ++k) v[k] = axes_[k].worth ? axes_[k].wa : std::numeric_limits<double>::quiet_NaN();
    return v;
}
Vec6d OdomCalibration::worthB() const {
    Vec6d v;
    for (int k = 0; k < 6; ++k) v[k] = axes_[k].worth ? axes_[k].wb : std::numeric_limits<double>::quiet_NaN();
    return v;
}
Vec6d OdomCalibration::sinceHeld() const {
    Vec6d v;
    for (int k = 0; k < 6; ++k) v[k] = axes_[k].since_m;
    return v;
}

Vec6d OdomCalibration::fitSigma(const SE3d& odom) const {
    const double d = odom.translation().norm();
    const Vec3d phi = logSO3(odom.linear());
    Vec6d s;
    for (int k = 0; k < 6; ++k) {
        if (!calibrated(k)) {
            s[k] = std::numeric_limits<double>::quiet_NaN();
            continue;
        }
        const Axis& a = axes_[k];
        const Eigen::Vector2d reg = regressor(k, d, k >= 3 ? phi[k - 3] : 0.0);
        const double floor = k >= 3 ? p_.sigma_floor_rot : p_.sigma_floor_xyz;
        s[k] = std::max(floor, std::sqrt(a.var * (1.0 + reg.dot(a.cov * reg))));
    }
    return s;
}

Vec3d OdomCalibration::drift() const { return {axes_[0].x[0], axes_[1].x[0], axes_[2].x[0]}; }
Vec3d OdomCalibration::rotationScale() const { return {axes_[3].x[0], axes_[4].x[0], axes_[5].x[0]}; }
Vec3d OdomCalibration::rotationPerM() const { return {axes_[3].x[1], axes_[4].x[1], axes_[5].x[1]}; }

}  // namespace superloc::fusion
