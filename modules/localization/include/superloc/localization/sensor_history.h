// What the Localizer keeps of its other sensors between scans: the IMU samples and the second
// odometry's (odom_alt) poses, in time order, and the look-ups a frame makes of them (the IMU
// over an interval, odom_alt's motion and covariance, gravity for a search).
#pragma once

#include <superloc/core/types.h>

#include <optional>
#include <vector>

namespace superloc::localization {

class SensorHistory {
   public:
    /// Samples must come in time order; a duplicate or an older one is ignored.
    void addImu(const ImuSample& s);
    void addOdomAlt(const PoseStamped& p);
    const std::vector<ImuSample>& imu() const { return imu_; }
    bool hasOdomAlt() const { return !odom_alt_.empty(); }

    /// Body motion from t0 to t1 measured by odom_alt (its poses interpolated at both times,
    /// read as body poses in the odometry's own frame): T_odom_body(t0)^-1 T_odom_body(t1).
    /// Empty when odom_alt does not cover both times (gap > 0.5 s or outside its span).
    std::optional<SE3d> odomAltDelta(double t0, double t1) const;
    /// odom_alt's reported covariance interpolated at t, when its samples carry one.
    std::optional<Mat6d> odomAltCovAt(double t) const;
    /// Roll and pitch of the IMU (map z up, no yaw) from its mean specific force over the half
    /// second before t, for a search without an IMU prediction; empty without samples, or when
    /// their mean is not within 20 % of `gravity` [m/s^2].
    std::optional<Mat3d> gravityAt(double t, double gravity) const;
    /// Forgets what no later frame needs: IMU older than one second before t, odom_alt older
    /// than two.
    void forgetBefore(double t);

   private:
    std::vector<ImuSample> imu_;
    Trajectory odom_alt_;
};

}  // namespace superloc::localization
