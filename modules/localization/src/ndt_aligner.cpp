#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/registration/ndt.h>
#include <superloc/localization/ndt_aligner.h>

namespace superloc::localization {

namespace {
pcl::PointCloud<pcl::PointXYZ>::Ptr toPcl(const std::vector<Vec3f>& pts) {
    pcl::PointCloud<pcl::PointXYZ>::Ptr c(new pcl::PointCloud<pcl::PointXYZ>);
    c->resize(pts.size());
    for (size_t i = 0; i < pts.size(); ++i) (*c)[i] = pcl::PointXYZ(pts[i].x(), pts[i].y(), pts[i].z());
    return c;
}
}  // namespace

struct NdtAligner::Impl {
    // PCL's align() is not const; the object is logically const for the caller.
    mutable pcl::NormalDistributionsTransform<pcl::PointXYZ, pcl::PointXYZ> ndt;
};

NdtAligner::NdtAligner(const std::vector<Vec3f>& target, const NdtParams& params)
    : impl_(std::make_unique<Impl>()) {
    impl_->ndt.setResolution(static_cast<float>(params.resolution));
    impl_->ndt.setStepSize(params.step_size);
    impl_->ndt.setTransformationEpsilon(params.epsilon);
    impl_->ndt.setMaximumIterations(params.max_iterations);
    impl_->ndt.setInputTarget(toPcl(target));
}

NdtAligner::~NdtAligner() = default;

AlignResult NdtAligner::align(const std::vector<Vec3f>& source, const SE3d& guess) const {
    AlignResult r;
    if (source.empty()) return r;
    impl_->ndt.setInputSource(toPcl(source));
    pcl::PointCloud<pcl::PointXYZ> aligned;
    impl_->ndt.align(aligned, guess.matrix().cast<float>());
    r.converged = impl_->ndt.hasConverged();
    r.iterations = impl_->ndt.getFinalNumIteration();
    r.T_target_source.matrix() = impl_->ndt.getFinalTransformation().cast<double>();
    // Re-orthonormalise after the float round trip.
    r.T_target_source.linear() =
        Eigen::Quaterniond(r.T_target_source.linear()).normalized().toRotationMatrix();
    return r;
}

}  // namespace superloc::localization
