#include <superloc/imu/rest_init.h>

#include <algorithm>
#include <cmath>

namespace superloc::imu {

RestInit initAtRest(const std::vector<ImuSample>& samples, double t0, const ImuParams& p) {
    RestInit out;
    Vec3d acc_sum = Vec3d::Zero(), gyro_sum = Vec3d::Zero();
    double n_sum = 0, n_sq = 0, gyro_norm_sum = 0;
    for (const auto& s : samples) {
        if (s.t < t0) continue;
        if (s.t > t0 + p.init_window) break;
        acc_sum += s.acc;
        gyro_sum += s.gyro;
        const double n = s.acc.norm();
        n_sum += n;
        n_sq += n * n;
        gyro_norm_sum += s.gyro.norm();
        ++out.samples;
    }
    if (out.samples < 10) return out;
    const double k = static_cast<double>(out.samples);
    const double mean_n = n_sum / k;
    const double std_n = std::sqrt(std::max(0.0, n_sq / k - mean_n * mean_n));
    if (std_n > p.rest_acc_std || gyro_norm_sum / k > p.rest_gyro_max) return out;
    out.at_rest = true;
    out.bias.gyro = gyro_sum / k;
    out.up_imu = (acc_sum / k).normalized();
    out.acc_norm = mean_n;
    return out;
}

double tiltDisagreement(const RestInit& r, const Mat3d& R_map_imu) {
    const double c = std::clamp((R_map_imu * r.up_imu).dot(Vec3d::UnitZ()), -1.0, 1.0);
    return std::acos(c);
}

}  // namespace superloc::imu
