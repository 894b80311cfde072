// The Localizer façade (localizer.h): the map and its preparation, the inputs, and one frame's
// path through the Tracker, the HealthMonitor and the Recovery.
#include <superloc/core/config.h>
#include <superloc/core/timing.h>
#include <superloc/localization/localizer.h>
#include <superloc/localization/ndt_aligner.h>

#include <ctime>

namespace superloc::localization {

namespace {
using Clock = SteadyClock;
double threadCpuMs() {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return 1e3 * static_cast<double>(ts.tv_sec) + 1e-6 * static_cast<double>(ts.tv_nsec);
}
}  // namespace

PreparedMap::PreparedMap() = default;
PreparedMap::PreparedMap(PreparedMap&&) noexcept = default;
PreparedMap& PreparedMap::operator=(PreparedMap&&) noexcept = default;
PreparedMap::~PreparedMap() = default;

Localizer::Localizer(const LocalizerParams& params, std::shared_ptr<const map::PriorMap> map)
    : mrpt::system::COutputLogger("Localizer"),
      params_(params),
      variant_(makeMethodVariant(params.loc.method, params.fusion, params.risk)),
      health_(params.health),
      start_(params_.relocalization, params.features.max_range),
      tracker_(params_, variant_, sensors_, *this),
      recovery_(
          params_,
          [this](Frame& f, const fusion::FrameState& start, VerifyAs as, const TrackReport& base) {
              return tracker_.solveFrom(f, start, as, base);
          },
          sensors_, *this),
      outputs_(params.risk) {
    setMap(std::move(map));
}

Localizer::~Localizer() = default;

PreparedMap Localizer::prepareMap(const LocalizerParams& params, std::shared_ptr<const map::PriorMap> map) {
    if (!map || map->size() == 0) throw ConfigError("Localizer: the prior map is empty");
    PreparedMap p;
    p.map = std::move(map);
    if (makeMethodVariant(params.loc.method, params.fusion, params.risk).registration ==
        RegistrationKind::Ndt) {
        NdtParams np;
        np.resolution = params.loc.ndt_resolution;
        np.step_size = params.loc.ndt_step_size;
        np.epsilon = params.loc.ndt_epsilon;
        np.max_iterations = params.loc.ndt_max_iterations;
        p.ndt = std::make_unique<NdtAligner>(p.map->points(), np);
    }
    if (params.relocalization.enabled) p.search = std::make_unique<reloc::GlobalSearch>(*p.map, params.global_search);
    return p;
}

void Localizer::setMap(PreparedMap&& prepared) {
    if (!prepared.map || prepared.map->size() == 0) throw ConfigError("Localizer: the prior map is empty");
    if (static_cast<bool>(prepared.ndt) != (variant_.registration == RegistrationKind::Ndt) ||
        static_cast<bool>(prepared.search) != params_.relocalization.enabled)
        throw ConfigError("Localizer::setMap: the map was prepared for other parameters");
    // The old search refers to the old map: replace it before the map it may outlive.
    search_ = std::move(prepared.search);
    ndt_ = std::move(prepared.ndt);
    map_ = std::move(prepared.map);
    tracker_.setMap(map_, ndt_.get());
    recovery_.setSearch(search_.get());
    if (search_) search_->setMinLoggingLevel(getMinLoggingLevel());
}

void Localizer::setMap(std::shared_ptr<const map::PriorMap> map) { setMap(prepareMap(params_, std::move(map))); }

void Localizer::relocalize(const std::optional<reloc::SearchRegion>& region) { recovery_.relocalize(region); }

void Localizer::setInitialPose(const SE3d& T_map_lidar, const std::string& what) {
    if (start_.give(T_map_lidar, what, *map_, search_ != nullptr) == StartPose::Decision::Search) {
        MRPT_LOG_WARN_FMT("%s: localizing the first scan by the global search instead", start_.what().c_str());
        relocalize();
    }
}

void Localizer::setInitialPose(const Trajectory& traj, const std::string& what) { start_.giveTrajectory(traj, what); }

void Localizer::addImu(const ImuSample& s) { sensors_.addImu(s); }

void Localizer::addOdomAlt(const PoseStamped& p) { sensors_.addOdomAlt(p); }

FrameReport Localizer::process(const Scan& scan, FrameOutputs* out) {
    if (frames_ == 0) {
        // An initial pose from a trajectory: the pose at this first scan's time (checked against
        // the map's bounds before the frame's time is taken, as a pose given directly is).
        bool covered = true;
        const auto d = start_.atFirstScan(scan.t, *map_, search_ != nullptr, covered);
        if (d && !covered)
            MRPT_LOG_WARN_FMT("%s does not cover the first scan's time %.3f s: its first pose is the initial pose",
                              start_.what().c_str(), scan.t);
        if (d == StartPose::Decision::Search) {
            MRPT_LOG_WARN_FMT("%s: localizing the first scan by the global search instead", start_.what().c_str());
            relocalize();
        }
    }
    const auto t_start = Clock::now();
    const double cpu_start = threadCpuMs();
    // Steps 1-2 (Tracker): prediction and features.
    Frame& f = frame_;
    tracker_.begin(scan, start_.firstPose(), f);
    // A frame without a pose (relocalize(), or candidates tracked) is localized by the Recovery
    // alone; any other by the Tracker (steps 3-6: registration, fusion, covariance).
    const bool requested = recovery_.requested();
    const bool velocity_unknown = tracker_.velocityUnknown(f, !requested);
    FrameSolution sol;
    if (requested) {
        sol.state = f.start;
        sol.report = f.report;
        // Localized by the Recovery alone: lost until it takes a pose.
        sol.report.diverged = true;
        sol.report.diverged_reason = Divergence::NoPose;
    } else {
        sol = tracker_.track(f, velocity_unknown);
    }
    // The frame's report, assembled here and only here: from what the Tracker gave, the
    // Recovery's decisions, and the health checks' verdict (judge: the checks against the run's
    // reference as it stands, a value the Recovery is handed too).
    FrameReport rep(frames_++, scan.t, sol.report);
    rep.coarse_start = velocity_unknown && tracker_.registration().traits().coarse_to_fine;
    const HealthJudge judge = health_.judge();
    Verdict verdict;
    bool restart = false;  // the next frame starts with its velocity unknown
    // A decision of the Recovery: a pose it took replaces the frame's solve (the frame keeps its
    // own times) and is judged afresh (unless it keeps the frame's verdict); a lost frame may
    // report the best pose found; what the search did and its times; then the evidence, in
    // order. The last pose taken decides the restart.
    const auto apply = [&](RecoveryDecision d) {
        if (d.taken) {
            const StageTimes ms = rep.ms;
            sol = std::move(*d.taken);
            rep.setTrack(sol.report);
            rep.ms = ms;
            rep.recovered = rep.recovered || d.recovered;
            rep.measurePrediction();
            if (!d.keep_verdict) verdict = judge(rep);
            restart = d.restart;
        }
        if (d.shown) {
            rep.T_map_lidar = d.shown->T_map_lidar;
            rep.T_map_imu = d.shown->T_map_imu;
        }
        if (d.reloc) rep.reloc = std::move(*d.reloc);
        rep.ms.solve += d.ms;
        for (const HealthEvidence e : d.evidence) verdict = judge.amend(verdict, e);
    };
    if (requested) apply(recovery_.withoutPose(f, OwnPose{sol, rep, judge(rep)}, judge));
    // Step 7: health, then the Recovery: a given start checked within its uncertainty, a lost or
    // doubtful frame searched (unless this frame was the search's).
    rep.imu_drift_deg = requested ? 0.0 : health_.imuDrift(rep);
    rep.measurePrediction();
    verdict = judge(rep);
    if (f.first && !requested && start_.given() && search_ && verdict.health != Health::Lost)
        apply(recovery_.checkStart(f, *start_.given(), OwnPose{sol, rep, verdict}, judge));
    apply(recovery_.recoverIfLost(f, !requested, OwnPose{sol, rep, verdict}, judge));
    // A frame whose own registration is in doubt (not converged, or fitting clearly worse than
    // this map gives) reports, and carries, what it knew without its scan (doc/method.md §4).
    if (sol.post && !rep.recovered && verdict.checks.inDoubt()) rep.cov = tracker_.dropScan(sol);
    rep.setVerdict(verdict);
    // The frame is final. The health monitor commits it once (the reference, and the drift
    // check's chain, which goes on through frames the IMU predicted from the one before and
    // their own registration solved); the next frame starts from what the Recovery decided.
    const bool chained = f.pred.used_imu && !rep.recovered && !restart;
    const Recovery::NextFrame next = recovery_.endFrame(f, sol.state, rep, restart);
    health_.commit(rep, chained);
    tracker_.end(f, next.state, sol, rep, requested, recovery_.pending(), next.restart);
    sensors_.forgetBefore(scan.t);
    rep.ms.total = msSince(t_start);
    rep.ms.total_cpu = threadCpuMs() - cpu_start;
    if (out) outputs_.fill(scan, f.features, sol, *out);
    tracker_.recycle(std::move(sol.corr));
    return rep;
}

}  // namespace superloc::localization
