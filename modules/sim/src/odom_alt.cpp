#include <mrpt/config/CConfigFileBase.h>
#include <superloc/core/config.h>
#include <superloc/core/se3.h>
#include <superloc/sim/odom_alt.h>

#include <algorithm>
#include <cmath>
#include <random>

namespace superloc::sim {

namespace {
/// A direction uniform on the sphere: three normal draws, normalized (the same expression as
/// the simulator always used, so the seeded streams, and every committed figure, are unchanged).
Vec3d randomUnit(std::mt19937_64& rng, std::normal_distribution<double>& n) {
    const Vec3d v(n(rng), n(rng), n(rng));
    return v / std::max(1e-9, v.norm());
}
}  // namespace

void OdomAltParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& c,
                                       const std::string& s) {
    MRPT_LOAD_CONFIG_VAR(enabled, bool, c, s);
    MRPT_LOAD_CONFIG_VAR(label, string, c, s);
    MRPT_LOAD_CONFIG_VAR(rate_hz, double, c, s);
    MRPT_LOAD_CONFIG_VAR(drift_per_m, double, c, s);
    MRPT_LOAD_CONFIG_VAR(drift_per_rad, double, c, s);
    MRPT_LOAD_CONFIG_VAR(trans_noise, double, c, s);
    MRPT_LOAD_CONFIG_VAR(rot_noise_deg, double, c, s);
    MRPT_LOAD_CONFIG_VAR(jump_every, double, c, s);
    MRPT_LOAD_CONFIG_VAR(jump_xyz, double, c, s);
    MRPT_LOAD_CONFIG_VAR(jump_deg, double, c, s);
    drift_axis = c.read_string(s, "drift_axis", drift_axis);
    MRPT_LOAD_CONFIG_VAR(slip_deg_per_m, double, c, s);
    MRPT_LOAD_CONFIG_VAR(scale_sigma, double, c, s);
    MRPT_LOAD_CONFIG_VAR(lateral_sigma, double, c, s);
    MRPT_LOAD_CONFIG_VAR(vertical_sigma, double, c, s);
    MRPT_LOAD_CONFIG_VAR(heading_sigma_deg, double, c, s);
    MRPT_LOAD_CONFIG_VAR(wander_length, double, c, s);
    MRPT_LOAD_CONFIG_VAR(change_every_m, double, c, s);
}

void OdomAltParams::saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const {
    MRPT_SAVE_CONFIG_VAR_COMMENT(enabled, "write odom_alt observations");
    MRPT_SAVE_CONFIG_VAR_COMMENT(label, "CObservationRobotPose label");
    MRPT_SAVE_CONFIG_VAR_COMMENT(rate_hz, "[Hz]");
    MRPT_SAVE_CONFIG_VAR_COMMENT(drift_per_m, "[m/m] translation drift per metre travelled");
    MRPT_SAVE_CONFIG_VAR_COMMENT(drift_per_rad, "[rad/rad] rotation drift per radian turned");
    MRPT_SAVE_CONFIG_VAR_COMMENT(trans_noise, "[m] 1-sigma white noise per increment");
    MRPT_SAVE_CONFIG_VAR_COMMENT(rot_noise_deg, "[deg] 1-sigma white noise per increment");
    MRPT_SAVE_CONFIG_VAR_COMMENT(jump_every, "[s] a jump this often, not in the covariance (0 = none)");
    MRPT_SAVE_CONFIG_VAR_COMMENT(jump_xyz, "[m] a jump's translation (random body direction)");
    MRPT_SAVE_CONFIG_VAR_COMMENT(jump_deg, "[deg] a jump's rotation (random axis)");
    MRPT_SAVE_CONFIG_VAR_COMMENT(drift_axis, "body direction of the translation drift: random | x | y | z");
    MRPT_SAVE_CONFIG_VAR_COMMENT(slip_deg_per_m, "[deg/m] heading slip about body z, not in the covariance (0 = none)");
    MRPT_SAVE_CONFIG_VAR_COMMENT(scale_sigma, "[-] wandering scale error, stationary 1-sigma (0 = none; doc/sim.md)");
    MRPT_SAVE_CONFIG_VAR_COMMENT(lateral_sigma, "[m/m] wandering drift along body y per metre, 1-sigma");
    MRPT_SAVE_CONFIG_VAR_COMMENT(vertical_sigma, "[m/m] wandering drift along body z per metre, 1-sigma");
    MRPT_SAVE_CONFIG_VAR_COMMENT(heading_sigma_deg, "[deg/m] wandering heading rate (yaw per metre), 1-sigma");
    MRPT_SAVE_CONFIG_VAR_COMMENT(wander_length, "[m] correlation length of the wandering error over distance (0: held for the run)");
    MRPT_SAVE_CONFIG_VAR_COMMENT(change_every_m, "[m] the wandering error drawn afresh this often (0 = never)");
}

void OdomAltParams::validate() const {
    if (!(rate_hz >= 1 && rate_hz <= 200))
        throw ConfigError("[odom_alt] rate_hz must be in [1, 200]");
    if (!(drift_per_m >= 0 && drift_per_rad >= 0 && trans_noise >= 0 && rot_noise_deg >= 0))
        throw ConfigError("[odom_alt] drift and noise values must be >= 0");
    if (!(jump_every >= 0 && jump_xyz >= 0 && jump_deg >= 0) || !std::isfinite(jump_every + jump_xyz + jump_deg))
        throw ConfigError("[odom_alt] jump_every, jump_xyz and jump_deg must be finite and >= 0");
    if (drift_axis != "random" && drift_axis != "x" && drift_axis != "y" && drift_axis != "z")
        throw ConfigError("[odom_alt] drift_axis = '" + drift_axis + "' (use random, x, y or z)");
    if (!(slip_deg_per_m >= 0 && std::isfinite(slip_deg_per_m)))
        throw ConfigError("[odom_alt] slip_deg_per_m must be finite and >= 0");
    for (const auto& [v, name] : {std::pair{scale_sigma, "scale_sigma"}, {lateral_sigma, "lateral_sigma"},
                                  {vertical_sigma, "vertical_sigma"}, {heading_sigma_deg, "heading_sigma_deg"},
                                  {wander_length, "wander_length"}, {change_every_m, "change_every_m"}})
        if (!(v >= 0 && std::isfinite(v)))
            throw ConfigError(std::string("[odom_alt] ") + name + " must be finite and >= 0");
    if (!(scale_sigma < 0.5)) throw ConfigError("[odom_alt] scale_sigma must be < 0.5");
}

OdomAltSimulator::OdomAltSimulator(const OdomAltParams& p, uint64_t seed)
    : p_(p), rng_(seed), jump_rng_(seed ^ 0x6a756d70ULL), wander_rng_(seed ^ 0x77616e64ULL) {
    u_ = randomUnit(rng_, n01_);  // drawn whatever drift_axis says: the rest of the stream stays the same
    if (p_.drift_axis == "x" || p_.drift_axis == "y" || p_.drift_axis == "z")
        u_ = Vec3d::Unit(p_.drift_axis[0] - 'x');
    sign_ = n01_(rng_) < 0 ? -1.0 : 1.0;
    std::mt19937_64 slip_rng(seed ^ 0x736c6970ULL);
    slip_sign_ = std::uniform_int_distribution<int>(0, 1)(slip_rng) ? 1.0 : -1.0;
    drawWander();
    next_change_ = p_.change_every_m;
}

Eigen::Vector4d OdomAltSimulator::wanderSigma() const {
    return {p_.scale_sigma, p_.lateral_sigma, p_.vertical_sigma, p_.heading_sigma_deg * M_PI / 180};
}

void OdomAltSimulator::drawWander() {
    std::normal_distribution<double> n(0.0, 1.0);
    const Eigen::Vector4d s = wanderSigma();
    for (int i = 0; i < 4; ++i) wander_[i] = s[i] * n(wander_rng_);
}

PoseStamped OdomAltSimulator::step(double t, const SE3d& T_map_imu) {
    PoseStamped out;
    out.t = t;
    if (first_) {
        first_ = false;
        odom_ = SE3d::Identity();
        next_jump_ = t + p_.jump_every;
    } else {
        const SE3d dT = last_gt_.inverse() * T_map_imu;
        const double d = dT.translation().norm();
        const Vec3d phi = logSO3(dT.linear());
        const double a = phi.norm();
        dist_ += d;
        angle_ += a;
        const Vec3d nt(n01_(rng_), n01_(rng_), n01_(rng_)), nr(n01_(rng_), n01_(rng_), n01_(rng_));
        Vec3d dt = p_.drift_per_m * d * u_ + p_.trans_noise * nt;
        Vec3d dr = sign_ * p_.drift_per_rad * phi + (p_.rot_noise_deg * M_PI / 180) * nr;
        dr.z() += slip_sign_ * p_.slip_deg_per_m * M_PI / 180 * d;
        // The wandering error over this increment, at its current values; then the processes
        // step on by d (exact discretisation of the Ornstein-Uhlenbeck process in distance).
        dt += wander_[0] * dT.translation() + Vec3d(0, wander_[1] * d, wander_[2] * d);
        dr.z() += wander_[3] * d;
        if (p_.wander_length > 0 && d > 0) {
            const double rho = std::exp(-d / p_.wander_length);
            const double q = std::sqrt(std::max(0.0, 1.0 - rho * rho));
            std::normal_distribution<double> n(0.0, 1.0);
            const Eigen::Vector4d s = wanderSigma();
            for (int i = 0; i < 4; ++i) wander_[i] = rho * wander_[i] + q * s[i] * n(wander_rng_);
        }
        if (p_.change_every_m > 0 && dist_ >= next_change_) {
            drawWander();
            next_change_ += p_.change_every_m;
        }
        SE3d E = SE3d::Identity();
        E.linear() = expSO3(dr);
        E.translation() = dt;
        if (p_.jump_every > 0 && t >= next_jump_) {
            next_jump_ += p_.jump_every;
            std::normal_distribution<double> n(0.0, 1.0);
            SE3d J = SE3d::Identity();
            J.translation() = p_.jump_xyz * randomUnit(jump_rng_, n);
            J.linear() = expSO3(p_.jump_deg * M_PI / 180 * randomUnit(jump_rng_, n));
            E = E * J;
        }
        odom_ = orthonormalize(odom_ * dT * E);
    }
    ++count_;
    last_gt_ = T_map_imu;
    // Reported uncertainty: the accumulated drift bound plus the accumulated white noise.
    const double st = p_.drift_per_m * dist_ + p_.trans_noise * std::sqrt(double(count_));
    const double sr =
        p_.drift_per_rad * angle_ + (p_.rot_noise_deg * M_PI / 180) * std::sqrt(double(count_));
    Mat6d cov = Mat6d::Zero();
    cov.diagonal() << Vec3d::Constant(std::max(st * st, 1e-8)),
        Vec3d::Constant(std::max(sr * sr, 1e-10));
    out.pose = odom_;
    out.cov = cov;
    return out;
}

}  // namespace superloc::sim
