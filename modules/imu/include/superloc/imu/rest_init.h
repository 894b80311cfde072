// Initialisation of the gyroscope bias and the gravity direction when the robot starts at rest.
#pragma once

#include <superloc/core/types.h>
#include <superloc/imu/imu_params.h>
#include <superloc/imu/preintegration.h>

#include <vector>

namespace superloc::imu {

struct RestInit {
    bool at_rest = false;   ///< the window passed the rest test (else the fields below are unset)
    size_t samples = 0;     ///< samples in the window
    ImuBias bias;           ///< gyro bias = mean angular rate; acc bias left at zero
    Vec3d up_imu = Vec3d::UnitZ();  ///< unit "up" (mean specific force) in the IMU frame
    double acc_norm = 0;    ///< [m/s^2] mean |acc|
};

/// Rest test over the samples with t in [t0, t0 + p.init_window]: std of |acc| below
/// p.rest_acc_std and mean |gyro| below p.rest_gyro_max.
RestInit initAtRest(const std::vector<ImuSample>& samples, double t0, const ImuParams& p);

/// Angle [rad] between the IMU's measured up direction and the map's z axis seen through the
/// rotation R_map_imu: how far the given initial attitude is from what gravity says.
double tiltDisagreement(const RestInit& r, const Mat3d& R_map_imu);

}  // namespace superloc::imu
