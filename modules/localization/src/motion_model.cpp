// Step 1: the prediction of a frame (motion_model.h).
#include <superloc/core/se3.h>
#include <superloc/imu/rest_init.h>
#include <superloc/localization/motion_model.h>

#include <algorithm>

namespace superloc::localization {

Prediction predictMotion(const fusion::FrameState& prev, const std::optional<fusion::FrameState>& prev_prev, double t,
                         const SensorHistory& sensors, const OdomFusion& policy, bool use_imu, const Vec3d& g_map,
                         imu::Preintegration& pre) {
    Prediction pr;
    const auto& imu = sensors.imu();
    const bool imu_covers = use_imu && imu::coversInterval(imu, prev.t, t, 0.05);
    if (imu_covers && imu::integrateInterval(imu, prev.t, t, pre) > 0) {
        // With IMU: Forster eq. 33 from the previous state.
        const imu::NavState nav = pre.predict(prev.nav(), prev.bias(), g_map);
        pr.T_map_imu = nav.pose();
        pr.v = nav.v;
        pr.used_imu = true;
        pr.twist_from_imu = true;
        // Deskew twist: mean rate over the interval since the last scan (one sweep at the
        // sensor's rate), velocity in the body frame.
        pr.w_body = logSO3(pre.correctedDeltaR(prev.bias())) / pre.dt();
        pr.v_body = nav.R.transpose() * nav.v;
        return pr;
    }
    const SE3d T_prev = prev.T_map_imu();
    // Without IMU, with odom_alt where the method predicts from it (superloc: its motion with
    // the calibrated systematic error removed).
    if (policy.usesOdomAlt() && t > prev.t) {
        if (const auto d = sensors.odomAltDelta(prev.t, t)) {
            if (const auto m = policy.motion(*d)) {
                const Vec6d xi = toVec6(*m) / (t - prev.t);
                pr.T_map_imu = T_prev * *m;
                pr.v_body = xi.head<3>();
                // The sweep is deskewed with odom_alt's own rotation rate, not the calibrated
                // one: the calibration's rotation scale is learned from scans deskewed with this
                // rate, and a deskew's rotation error moves the registered attitude of a swaying
                // sensor by more than itself (the increments alternate in sign frame to frame).
                // Fed back, that loop grew the simulated corridor's 0.3 deg, 3 Hz pitch sway into
                // a 1-2 deg oscillation of the estimate (doc/method.md §2 "Without IMU").
                pr.w_body = toVec6(*d).tail<3>() / (t - prev.t);
                pr.v = T_prev.linear() * pr.v_body;
                pr.from_odom = true;
                return pr;
            }
        }
    }
    // Without IMU: constant velocity from the last two estimates.
    pr.T_map_imu = T_prev;
    if (prev_prev && prev.t > prev_prev->t) {
        const double dt_prev = prev.t - prev_prev->t;
        const Vec6d xi = toVec6(prev_prev->T_map_imu().inverse() * T_prev) / dt_prev;  // body twist
        pr.T_map_imu = T_prev * fromVec6(xi * (t - prev.t));
        pr.v_body = xi.head<3>();
        pr.w_body = xi.tail<3>();
        pr.v = T_prev.linear() * pr.v_body;
    }
    return pr;
}

Prediction predictFirst(const Scan& scan, const SE3d& T_map_imu, const SensorHistory& sensors, bool use_imu,
                        const imu::ImuParams& imu_params, imu::ImuBias& bias, std::optional<double>& tilt_deg) {
    Prediction pred;
    pred.T_map_imu = T_map_imu;
    bias = imu::ImuBias{};
    tilt_deg.reset();
    const auto& imu = sensors.imu();
    if (use_imu && !imu.empty()) {
        const auto rest = imu::initAtRest(imu, imu.front().t, imu_params);
        if (rest.at_rest) {
            bias = rest.bias;
            pred.at_rest = true;
            tilt_deg = imu::tiltDisagreement(rest, T_map_imu.linear()) / kDeg;
        }
    }
    // Deskew the first sweep by the gyro alone (the velocity is not known yet).
    if (use_imu && !scan.rel_time.empty()) {
        const double s_min = *std::min_element(scan.rel_time.begin(), scan.rel_time.end());
        imu::Preintegration sweep(bias);
        if (s_min < 0 && !imu.empty() && imu.front().t <= scan.t + s_min + 0.05 && imu.back().t >= scan.t - 0.05 &&
            imu::integrateInterval(imu, scan.t + s_min, scan.t, sweep) > 0) {
            pred.w_body = logSO3(sweep.deltaR()) / sweep.dt();
            pred.twist_from_imu = true;
        }
    }
    return pred;
}

}  // namespace superloc::localization
