#include <superloc/core/se3.h>
#include <superloc/features/deskew.h>

#include <algorithm>

namespace superloc::features {

SweepMotion SweepMotion::fromTwist(const Vec3d& v, const Vec3d& w, double duration, int samples) {
    std::vector<double> s;
    std::vector<SE3d> T;
    samples = std::max(samples, 2);
    for (int k = 0; k < samples; ++k) {
        const double sk = -duration + duration * k / (samples - 1);
        SE3d Tk = SE3d::Identity();
        Tk.linear() = expSO3(w * sk);
        Tk.translation() = v * sk;
        s.push_back(sk);
        T.push_back(Tk);
    }
    return fromSamples(s, T);
}

SweepMotion SweepMotion::fromSamples(const std::vector<double>& s, const std::vector<SE3d>& T_end_s) {
    SweepMotion m;
    for (size_t k = 0; k < s.size() && k < T_end_s.size(); ++k) {
        m.s_.push_back(static_cast<float>(s[k]));
        m.rot_.push_back(logSO3(T_end_s[k].linear()).cast<float>());
        m.trans_.push_back(T_end_s[k].translation().cast<float>());
    }
    return m;
}

void SweepMotion::at(float s, Eigen::Vector3f& rotvec, Eigen::Vector3f& trans) const {
    if (s <= s_.front()) {
        rotvec = rot_.front();
        trans = trans_.front();
        return;
    }
    if (s >= s_.back()) {
        rotvec = rot_.back();
        trans = trans_.back();
        return;
    }
    const size_t k = std::upper_bound(s_.begin(), s_.end(), s) - s_.begin();  // s_[k-1] <= s < s_[k]
    const float a = (s - s_[k - 1]) / (s_[k] - s_[k - 1]);
    rotvec = (1 - a) * rot_[k - 1] + a * rot_[k];
    trans = (1 - a) * trans_[k - 1] + a * trans_[k];
}

Vec3f SweepMotion::apply(const Vec3f& p, float s) const {
    Eigen::Vector3f r, t;
    at(s, r, t);
    const float th = r.norm();
    if (th < 1e-9f) return p + r.cross(p) + t;
    // Rodrigues on the point directly (cheaper than building the matrix).
    const Eigen::Vector3f k = r / th;
    const float c = std::cos(th), sn = std::sin(th);
    return p * c + k.cross(p) * sn + k * (k.dot(p)) * (1 - c) + t;
}

void deskewPoints(const std::vector<Vec3f>& points, const std::vector<float>& rel_time,
                  const std::vector<uint32_t>& idx, const SweepMotion& motion,
                  std::vector<Vec3f>& out) {
    out.resize(idx.size());
    const bool skip = motion.empty() || rel_time.size() != points.size();
    for (size_t k = 0; k < idx.size(); ++k) {
        const uint32_t i = idx[k];
        out[k] = skip ? points[i] : motion.apply(points[i], rel_time[i]);
    }
}

}  // namespace superloc::features
