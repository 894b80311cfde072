// RawlogReader: streams a rawlog in timestamp order through a bounded re-sort window.
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CObservationIMU.h>
#include <mrpt/obs/CObservationRobotPose.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/serialization/CArchive.h>
#include <mrpt/system/COutputLogger.h>
#include <superloc/core/mrpt_conversions.h>
#include <superloc/io/rawlog.h>

#include <algorithm>
#include <cmath>
#include <exception>
#include <filesystem>
#include <fstream>
#include <utility>
#include <queue>
#include <stdexcept>

#include "obs_to_scan.h"

namespace superloc::io {

double RawlogItem::time() const {
    return std::visit([](const auto& d) { return d.t; }, data);
}

namespace {
struct Pending {
    double t;
    size_t seq;  // read order: ties keep the file order
    RawlogItem item;
};
struct Later {
    bool operator()(const Pending& a, const Pending& b) const {
        return a.t != b.t ? a.t > b.t : a.seq > b.seq;
    }
};
}  // namespace

struct RawlogReader::Impl : public mrpt::system::COutputLogger {
    Impl() : mrpt::system::COutputLogger("RawlogReader") {}

    std::string path;
    RawlogParams params;
    RawlogStats stats;
    mrpt::io::CFileGZInputStream file;
    std::priority_queue<Pending, std::vector<Pending>, Later> heap;
    size_t entry = 0;  // rawlog entries read so far
    size_t seq = 0;
    bool eof = false;
    double newest = -INFINITY;  // latest timestamp read
    RawlogParams::ScanSelection selection;  // [rawlog] scans
    size_t lidar_index = 0;                 // LiDAR scans emitted or dropped so far
    size_t lidar_emitted = 0;               // LiDAR scans returned by next()
    bool gzipped = false;                   // the file starts with gzip's magic bytes
    std::exception_ptr error;               // a read error, thrown once the window is emptied

    std::string where() const { return path + ": entry " + std::to_string(entry) + ": "; }

    void warnOnce(size_t count, const std::string& what) {
        if (count == 1) MRPT_LOG_WARN_STREAM(path << ": " << what << " (counted, logged once)");
    }

    void push(RawlogItem&& item) {
        const double t = item.time();
        if (!std::isfinite(t))
            throw std::runtime_error(where() + "observation without a valid timestamp");
        if (t < newest - params.reorder_window - 1e-9)
            throw std::runtime_error(
                where() + "timestamp goes backwards by " + std::to_string(newest - t) +
                " s, more than [rawlog] reorder_window = " + std::to_string(params.reorder_window) +
                " s");
        newest = std::max(newest, t);
        heap.push(Pending{t, seq++, std::move(item)});
        stats.max_pending = std::max(stats.max_pending, heap.size());
    }

    void handle(const mrpt::obs::CObservation& obs) {
        using namespace mrpt::obs;
        RawlogItem item;
        Scan scan;
        const size_t invalid_before = stats.invalid_points;
        const auto conv = detail::lidarFromObservation(obs, params, scan, stats.invalid_points);
        if (conv == detail::LidarConversion::Unsupported) {
            warnOnce(++stats.unknown_observations,
                     "CObservationRotatingScan of a model without known beam angles skipped");
        } else if (conv == detail::LidarConversion::Ok) {
            if (invalid_before == 0 && stats.invalid_points > 0)
                warnOnce(1, "NaN/inf points dropped from scans");
            if (!params.lidar_label.empty() && scan.label != params.lidar_label) {
                ++stats.skipped_labels;
                auto& others = stats.other_lidar_labels;
                if (others.size() < 5 && std::find(others.begin(), others.end(), scan.label) == others.end())
                    others.push_back(scan.label);
                return;
            }
            if (scan.empty()) {
                warnOnce(++stats.empty_scans, "LiDAR observation (" +
                                                  std::string(obs.GetRuntimeClass()->className) +
                                                  ") without valid points skipped");
                return;
            }
            ++stats.lidar;
            item.kind = RawlogItem::Kind::Lidar;
            item.data = std::move(scan);
            push(std::move(item));
        } else if (const auto* imu = dynamic_cast<const CObservationIMU*>(&obs)) {
            if (!params.imu_label.empty() && imu->sensorLabel != params.imu_label) {
                ++stats.skipped_labels;
                return;
            }
            ImuSample s;
            s.t = mrpt::Clock::toDouble(imu->timestamp);
            bool ok = true;
            for (auto idx : {IMU_X_ACC, IMU_Y_ACC, IMU_Z_ACC, IMU_WX, IMU_WY, IMU_WZ})
                ok = ok && imu->has(idx) && std::isfinite(imu->get(idx));
            if (!ok) {
                warnOnce(++stats.invalid_imu, "IMU sample without finite acc+gyro skipped");
                return;
            }
            s.acc = Vec3d(imu->get(IMU_X_ACC), imu->get(IMU_Y_ACC), imu->get(IMU_Z_ACC));
            s.gyro = Vec3d(imu->get(IMU_WX), imu->get(IMU_WY), imu->get(IMU_WZ));
            ++stats.imu;
            item.kind = RawlogItem::Kind::Imu;
            item.data = s;
            push(std::move(item));
        } else if (const auto* rp = dynamic_cast<const CObservationRobotPose*>(&obs)) {
            const bool is_odom = rp->sensorLabel == params.odom_alt_label;
            const bool is_gt = rp->sensorLabel == params.gt_label;
            if (!is_odom && !is_gt) {
                warnOnce(++stats.other_pose_labels,
                         "CObservationRobotPose with label '" + rp->sensorLabel +
                             "' (neither odom_alt_label nor gt_label) skipped");
                return;
            }
            PoseStamped p;
            p.t = mrpt::Clock::toDouble(rp->timestamp);
            p.pose = toEigen(rp->pose.mean);
            p.cov = covFromMrpt(rp->pose.cov);
            if (!p.pose.matrix().allFinite())
                throw std::runtime_error(where() + "non-finite pose in '" + rp->sensorLabel + "'");
            if (is_odom)
                ++stats.odom_alt;
            else
                ++stats.gt;
            item.kind = is_odom ? RawlogItem::Kind::OdomAlt : RawlogItem::Kind::GroundTruth;
            item.data = p;
            push(std::move(item));
        } else {
            warnOnce(++stats.unknown_observations,
                     "observation of unused class " +
                         std::string(obs.GetRuntimeClass()->className) + " skipped");
        }
    }

    /// Reads one rawlog entry: an observation, a sensory frame or an action (ignored). Our
    /// own loop, because CRawlog's prints a trace and reports a corrupt file as a clean end.
    void readEntry() {
        mrpt::serialization::CSerializable::Ptr obj;
        const uint64_t start = file.getPosition();
        try {
            auto arch = mrpt::serialization::archiveFrom(file);
            arch >> obj;
        } catch (const mrpt::serialization::CExceptionEOF&) {
            // The end of the file before the next object's header is a clean end; inside an
            // object (bytes of it were read), the file was cut.
            if (file.getPosition() == start) {
                eof = true;
                return;
            }
            ++entry;
            throw std::runtime_error(where() + "corrupt or truncated rawlog: the file ends inside this entry");
        } catch (const std::exception& e) {
            ++entry;
            if (entry == 1 && !gzipped)
                throw std::runtime_error(path + ": not an MRPT rawlog (its first bytes are neither gzip "
                                                "nor an MRPT object)");
            std::string why = detail::firstLine(e.what());
            // MRPT's guess for a bad object header, misleading here (the reader reads both).
            const size_t hint = why.find(" Perhaps it's a gz-compressed stream?");
            if (hint != std::string::npos) why.erase(hint);
            for (char& c : why)  // a corrupt class name is raw bytes
                if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) > 0x7e) c = '?';
            throw std::runtime_error(where() + "corrupt or truncated rawlog: " + why);
        }
        ++entry;
        if (const auto obs = std::dynamic_pointer_cast<mrpt::obs::CObservation>(obj)) {
            handle(*obs);
        } else if (const auto sf = std::dynamic_pointer_cast<mrpt::obs::CSensoryFrame>(obj)) {
            for (const auto& o : *sf)
                if (o) handle(*o);
        } else if (!std::dynamic_pointer_cast<mrpt::obs::CActionCollection>(obj)) {
            throw std::runtime_error(where() + "not a rawlog entry: object of class " +
                                     std::string(obj ? obj->GetRuntimeClass()->className : "null"));
        }
    }
};

RawlogReader::RawlogReader(const std::string& path, const RawlogParams& params)
    : impl_(std::make_unique<Impl>()) {
    params.validate();
    impl_->path = path;
    impl_->params = params;
    impl_->selection = params.scanSelection();
    if (!std::filesystem::is_regular_file(path))
        throw std::runtime_error(path + ": rawlog not found");
    {
        std::ifstream head(path, std::ios::binary);
        unsigned char magic[2] = {0, 0};
        head.read(reinterpret_cast<char*>(magic), 2);
        impl_->gzipped = magic[0] == 0x1f && magic[1] == 0x8b;
    }
    if (!impl_->file.open(path)) throw std::runtime_error(path + ": cannot open rawlog");
}

RawlogReader::~RawlogReader() = default;

bool RawlogReader::next(RawlogItem& item) {
    auto& m = *impl_;
    // Emit the oldest pending item once nothing still unread can be older than it; LiDAR scans
    // outside [rawlog] scans are dropped here, in time order.
    // A read error (a corrupt or truncated entry, time going backwards) ends the reading, but
    // the items already in the window are returned first; the error comes after them.
    for (;;) {
        while (!m.eof && (m.heap.empty() || m.newest - m.heap.top().t <= m.params.reorder_window)) {
            try {
                m.readEntry();
            } catch (const std::exception&) {
                m.error = std::current_exception();
                m.eof = true;
            }
        }
        if (m.heap.empty()) {
            if (m.error) std::rethrow_exception(std::exchange(m.error, nullptr));
            return false;
        }
        item = std::move(const_cast<Pending&>(m.heap.top()).item);
        m.heap.pop();
        if (item.kind != RawlogItem::Kind::Lidar) return true;
        if (m.selection.contains(m.lidar_index++)) {
            ++m.lidar_emitted;
            return true;
        }
        ++m.stats.unselected_scans;
    }
}

std::string RawlogReader::noScanReason() const {
    const auto& m = *impl_;
    const auto& st = m.stats;
    const std::string& p = m.path;
    if (st.lidar > 0 && m.lidar_emitted == 0)
        return p + ": [rawlog] scans = '" + m.params.scans + "' selects none of its " +
               std::to_string(st.lidar) + " LiDAR scans (indices 0 to " + std::to_string(st.lidar - 1) + ")";
    if (st.lidar == 0 && !st.other_lidar_labels.empty()) {
        std::string labels;
        for (const auto& l : st.other_lidar_labels) labels += (labels.empty() ? "'" : ", '") + l + "'";
        return p + ": no LiDAR scan labelled [rawlog] lidar_label = '" + m.params.lidar_label +
               "' (its scans are labelled " + labels + ")";
    }
    if (st.lidar == 0 && st.empty_scans > 0)
        return p + ": its " + std::to_string(st.empty_scans) + " LiDAR observations have no valid point";
    return p + ": no LiDAR scan in the rawlog (" + std::to_string(m.entry) + " entries read: " +
           std::to_string(st.imu) + " IMU, " + std::to_string(st.odom_alt) + " odom_alt, " +
           std::to_string(st.gt) + " gt, " + std::to_string(st.unknown_observations) + " of unused classes)";
}

const RawlogStats& RawlogReader::stats() const { return impl_->stats; }
const std::string& RawlogReader::path() const { return impl_->path; }
mrpt::system::COutputLogger& RawlogReader::logger() { return *impl_; }

}  // namespace superloc::io
