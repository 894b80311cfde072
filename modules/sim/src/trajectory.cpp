#include <mrpt/config/CConfigFileBase.h>
#include <superloc/core/config.h>
#include <superloc/sim/trajectory.h>

#include <algorithm>
#include <cmath>

namespace superloc::sim {

MotionLimits TrajectoryParams::limits() const {
    MotionLimits l;
    l.max_speed = max_speed;
    l.max_yaw_rate = max_yaw_rate_deg * M_PI / 180;
    l.max_accel = max_accel;
    l.max_lat_accel = max_lat_accel;
    l.corner_radius = corner_radius;
    return l;
}

void TrajectoryParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& c,
                                          const std::string& s) {
    MRPT_LOAD_CONFIG_VAR(platform, string, c, s);
    MRPT_LOAD_CONFIG_VAR(max_speed, double, c, s);
    MRPT_LOAD_CONFIG_VAR(max_yaw_rate_deg, double, c, s);
    MRPT_LOAD_CONFIG_VAR(max_accel, double, c, s);
    MRPT_LOAD_CONFIG_VAR(max_lat_accel, double, c, s);
    MRPT_LOAD_CONFIG_VAR(corner_radius, double, c, s);
    MRPT_LOAD_CONFIG_VAR(body_height, double, c, s);
    MRPT_LOAD_CONFIG_VAR(knot_dt, double, c, s);
    MRPT_LOAD_CONFIG_VAR(pitch_follow, double, c, s);
    MRPT_LOAD_CONFIG_VAR(bob_amplitude, double, c, s);
    MRPT_LOAD_CONFIG_VAR(bob_frequency, double, c, s);
    MRPT_LOAD_CONFIG_VAR(sway_roll_deg, double, c, s);
    MRPT_LOAD_CONFIG_VAR(sway_pitch_deg, double, c, s);
    MRPT_LOAD_CONFIG_VAR(sway_yaw_deg, double, c, s);
    MRPT_LOAD_CONFIG_VAR(sway_frequency, double, c, s);
    MRPT_LOAD_CONFIG_VAR(ramp_time, double, c, s);
}

void TrajectoryParams::saveToConfigFile(mrpt::config::CConfigFileBase& c,
                                        const std::string& s) const {
    MRPT_SAVE_CONFIG_VAR_COMMENT(platform, "free text: car, handheld, legged, wheeled");
    MRPT_SAVE_CONFIG_VAR_COMMENT(max_speed, "[m/s]");
    MRPT_SAVE_CONFIG_VAR_COMMENT(max_yaw_rate_deg, "[deg/s] caps speed in turns");
    MRPT_SAVE_CONFIG_VAR_COMMENT(max_accel, "[m/s^2] along the path");
    MRPT_SAVE_CONFIG_VAR_COMMENT(max_lat_accel, "[m/s^2] caps speed in turns");
    MRPT_SAVE_CONFIG_VAR_COMMENT(corner_radius, "[m] fillet radius at waypoint corners");
    MRPT_SAVE_CONFIG_VAR_COMMENT(body_height, "[m] IMU height above the floor it moves on");
    MRPT_SAVE_CONFIG_VAR_COMMENT(knot_dt, "[s] B-spline knot spacing");
    MRPT_SAVE_CONFIG_VAR_COMMENT(pitch_follow, "[0..1] body pitch follows the path slope");
    MRPT_SAVE_CONFIG_VAR_COMMENT(bob_amplitude, "[m] vertical gait bobbing");
    MRPT_SAVE_CONFIG_VAR_COMMENT(bob_frequency, "[Hz]");
    MRPT_SAVE_CONFIG_VAR_COMMENT(sway_roll_deg, "[deg] roll sway amplitude");
    MRPT_SAVE_CONFIG_VAR_COMMENT(sway_pitch_deg, "[deg] pitch sway amplitude");
    MRPT_SAVE_CONFIG_VAR_COMMENT(sway_yaw_deg, "[deg] yaw sway amplitude");
    MRPT_SAVE_CONFIG_VAR_COMMENT(sway_frequency, "[Hz] roll; pitch at 2x, yaw at 0.5x");
    MRPT_SAVE_CONFIG_VAR_COMMENT(ramp_time, "[s] gait fade-in after the start");
}

void TrajectoryParams::validate() const {
    const auto need = [](bool ok, const char* what) {
        if (!ok) throw ConfigError(std::string("[trajectory] ") + what);
    };
    need(max_speed > 0, "max_speed must be > 0");
    need(max_yaw_rate_deg > 0, "max_yaw_rate_deg must be > 0");
    need(max_accel > 0, "max_accel must be > 0");
    need(max_lat_accel > 0, "max_lat_accel must be > 0");
    need(corner_radius >= 0, "corner_radius must be >= 0");
    need(knot_dt >= 0.02 && knot_dt <= 5, "knot_dt must be in [0.02, 5] s");
    need(pitch_follow >= 0 && pitch_follow <= 1, "pitch_follow must be in [0, 1]");
    need(bob_amplitude >= 0 && bob_frequency > 0 && sway_frequency > 0,
         "bob/sway amplitudes must be >= 0 and frequencies > 0");
    need(ramp_time > 0, "ramp_time must be > 0");
}

namespace {

// Quintic smoothstep and its two derivatives (C2 fade-in of the gait).
void smoothstep(double x, double T, double& e, double& de, double& dde) {
    const double u = std::clamp(x / T, 0.0, 1.0);
    e = u * u * u * (10 - 15 * u + 6 * u * u);
    de = (x < 0 || x > T) ? 0 : 30 * u * u * (1 - u) * (1 - u) / T;
    dde = (x < 0 || x > T) ? 0 : 60 * u * (1 - u) * (1 - 2 * u) / (T * T);
}

// amp * env(t) * sin(w t + ph): value and two derivatives.
void gait(double amp, double w, double ph, double t, double e, double de, double dde, double& y,
          double& dy, double& ddy) {
    const double s = std::sin(w * t + ph), c = std::cos(w * t + ph);
    y = amp * e * s;
    dy = amp * (de * s + e * w * c);
    ddy = amp * (dde * s + 2 * de * w * c - e * w * w * s);
}

}  // namespace

SmoothTrajectory::SmoothTrajectory(const DensePath& path, const TrajectoryParams& p, double t0,
                                   double max_duration)
    : p_(p), t0_(t0), dt_(p.knot_dt) {
    const double dur = std::min(path.duration(), max_duration);
    const int n = std::max(2, static_cast<int>(std::ceil(dur / dt_)) + 1);
    double prev_yaw = 0;
    for (int k = 0; k < n; ++k) {
        Vec3d tan;
        const Vec3d x = path.positionAt(k * dt_, &tan);
        const double horiz = std::hypot(tan.x(), tan.y());
        double yaw = horiz > 1e-6 ? std::atan2(tan.y(), tan.x()) : prev_yaw;
        if (k > 0) yaw = prev_yaw + std::remainder(yaw - prev_yaw, 2 * M_PI);  // unwrap
        prev_yaw = yaw;
        const double pitch = -p.pitch_follow * std::atan2(tan.z(), std::max(horiz, 1e-6));
        pos_ctrl_.push_back(x);
        rpy_ctrl_.push_back(Vec3d(0, pitch, yaw));
    }
    // Triple first control point: the spline starts exactly there at rest.
    pos_ctrl_.insert(pos_ctrl_.begin(), 2, pos_ctrl_.front());
    rpy_ctrl_.insert(rpy_ctrl_.begin(), 2, rpy_ctrl_.front());
    pos_ctrl_.push_back(pos_ctrl_.back());
    rpy_ctrl_.push_back(rpy_ctrl_.back());
    // Segments: ctrl.size() - 3; the last one is only partly used.
    duration_ = std::min(dur, (pos_ctrl_.size() - 3) * dt_ - 1e-9);
    t_end_ = t0_ + duration_;
}

SmoothTrajectory::Eval SmoothTrajectory::spline(const std::vector<Vec3d>& c, double t) const {
    const double x = (t - t0_) / dt_;
    const int nseg = static_cast<int>(c.size()) - 3;
    const int i = std::clamp(static_cast<int>(std::floor(x)), 0, nseg - 1);
    const double u = std::clamp(x - i, 0.0, 1.0);
    const double u2 = u * u, u3 = u2 * u;
    // Uniform cubic B-spline basis and derivatives (w.r.t. u).
    const double b0 = (1 - u) * (1 - u) * (1 - u) / 6, b1 = (3 * u3 - 6 * u2 + 4) / 6,
                 b2 = (-3 * u3 + 3 * u2 + 3 * u + 1) / 6, b3 = u3 / 6;
    const double d0 = -(1 - u) * (1 - u) / 2, d1 = (3 * u2 - 4 * u) / 2,
                 d2 = (-3 * u2 + 2 * u + 1) / 2, d3 = u2 / 2;
    const double e0 = 1 - u, e1 = 3 * u - 2, e2 = -3 * u + 1, e3 = u;
    Eval r;
    r.x = b0 * c[i] + b1 * c[i + 1] + b2 * c[i + 2] + b3 * c[i + 3];
    r.dx = (d0 * c[i] + d1 * c[i + 1] + d2 * c[i + 2] + d3 * c[i + 3]) / dt_;
    r.ddx = (e0 * c[i] + e1 * c[i + 1] + e2 * c[i + 2] + e3 * c[i + 3]) / (dt_ * dt_);
    return r;
}

BodyState SmoothTrajectory::at(double t_in) const {
    const double t = std::clamp(t_in, t0_, t_end_);
    Eval pos = spline(pos_ctrl_, t);
    Eval rpy = spline(rpy_ctrl_, t);

    // Gait: vertical bobbing and roll/pitch/yaw sway, faded in after the start.
    double e, de, dde;
    smoothstep(t - t0_, p_.ramp_time, e, de, dde);
    const double tl = t - t0_, d2r = M_PI / 180, w = 2 * M_PI * p_.sway_frequency;
    double y, dy, ddy;
    gait(p_.bob_amplitude, 2 * M_PI * p_.bob_frequency, 0.0, tl, e, de, dde, y, dy, ddy);
    pos.x.z() += y, pos.dx.z() += dy, pos.ddx.z() += ddy;
    const double amps[3] = {p_.sway_roll_deg * d2r, p_.sway_pitch_deg * d2r, p_.sway_yaw_deg * d2r};
    const double freqs[3] = {w, 2 * w, 0.5 * w}, phases[3] = {0.3, 1.1, 2.0};
    for (int k = 0; k < 3; ++k) {
        gait(amps[k], freqs[k], phases[k], tl, e, de, dde, y, dy, ddy);
        rpy.x[k] += y, rpy.dx[k] += dy, rpy.ddx[k] += ddy;
    }

    const double r = rpy.x[0], pch = rpy.x[1], yw = rpy.x[2];
    BodyState s;
    s.t = t;
    const Mat3d R = (Eigen::AngleAxisd(yw, Vec3d::UnitZ()) *
                     Eigen::AngleAxisd(pch, Vec3d::UnitY()) * Eigen::AngleAxisd(r, Vec3d::UnitX()))
                        .toRotationMatrix();
    s.T_map_body.linear() = R;
    s.T_map_body.translation() = pos.x;
    s.vel = pos.dx;
    s.acc = pos.ddx;
    // ZYX Euler rates -> body angular velocity.
    const double dr = rpy.dx[0], dp = rpy.dx[1], dyw = rpy.dx[2];
    s.omega_body =
        Vec3d(dr - std::sin(pch) * dyw, std::cos(r) * dp + std::sin(r) * std::cos(pch) * dyw,
              -std::sin(r) * dp + std::cos(r) * std::cos(pch) * dyw);
    return s;
}

}  // namespace superloc::sim
