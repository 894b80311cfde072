// The Localizer's link to the alignment risk and the relative-pose prior (DESIGN §5): the risk
// inputs from the correspondences, odom_alt's relative motion, and the prior hook that the
// active-fusion methods (issue 5) fill in.
#include <superloc/core/se3.h>
#include <superloc/localization/localizer.h>

namespace superloc::localization {

std::vector<risk::Correspondence> Localizer::riskInputs(const SE3d& T, const Vec3d& origin) const {
    std::vector<risk::Correspondence> out;
    out.reserve(corr_.size());
    const Mat3d Rt = T.linear().transpose();
    for (const auto& c : corr_) {
        risk::Correspondence r;
        r.p = c.p - origin;  // relative to the sensor, body axes
        const Vec3d x = T * c.p;
        Vec3d n;
        switch (c.type) {
            case features::FeatureType::Plane: n = c.n; r.type = risk::CorrespondenceType::Plane; break;
            case features::FeatureType::Line: {
                const Vec3d e = x - c.q;
                n = e - e.dot(c.n) * c.n;
                r.type = risk::CorrespondenceType::Line;
                break;
            }
            default: n = x - c.q; r.type = risk::CorrespondenceType::Point; break;
        }
        n = Rt * n;
        if (n.dot(r.p) > 0) n = -n;  // toward the sensor
        r.n = n;
        r.weight = c.weight;
        out.push_back(r);
    }
    return out;
}

std::optional<SE3d> Localizer::odomAltDelta(double t0, double t1) const {
    const auto a = interpolateAt(odom_alt_, t0, 0.5, 1e-3);
    const auto b = interpolateAt(odom_alt_, t1, 0.5, 1e-3);
    if (!a || !b) return std::nullopt;
    return orthonormalize(a->inverse() * *b);
}

std::optional<fusion::RelativePosePrior> Localizer::activePrior(const risk::RiskReport&) const {
    // icp and ndt use no prior; superloc / passive / eigen_remap fill this in (issue 5).
    return std::nullopt;
}

}  // namespace superloc::localization
