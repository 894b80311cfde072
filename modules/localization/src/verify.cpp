// Verifier: a pose tried for the current scan, solved and judged (verify.h).
#include <superloc/localization/verify.h>

namespace superloc::localization {

Attempt Verifier::verify(Frame& f, const fusion::FrameState& start, const FrameReport& base, VerifyAs as,
                         const HealthJudge& judge) const {
    Attempt a;
    a.rep = base;
    a.sol = solve_(f, start, as, base.track());
    a.rep.setTrack(a.sol.report);
    a.rep.measurePrediction();
    a.verdict = judge(a.rep);
    return a;
}

std::vector<Attempt> Verifier::verify(Frame& f, const std::vector<SE3d>& poses, const FrameReport& base,
                                      VerifyAs as, const HealthJudge& judge) const {
    std::vector<Attempt> out;
    out.reserve(poses.size());
    for (const SE3d& T : poses) {
        fusion::FrameState start;
        start.setBias(f.prev.bias());
        start.setPose(T * f.scan->T_imu_lidar.inverse());
        out.push_back(verify(f, start, base, as, judge));
    }
    return out;
}

bool Verifier::fits(const FrameReport& rep, const Verdict& v) const {
    const HealthChecks& c = v.checks;
    return !c.not_converged && v.health != Health::Lost && !c.badFit() &&
           (v.inlier_reference > 0 || rep.inlier_ratio >= params_.accept_inlier_ratio);
}

}  // namespace superloc::localization
