// Bag -> rawlog, shared by the ROS 1 (.bag), ROS 2 (.db3) and MCAP readers: topic resolution
// ([rosbag] section), the static transform tree, and the message -> observation conversion. Two
// passes: first the static transforms (they may be recorded after the first scans) and every
// mapped message's header (frames, stamps, record times: the clock of each topic and the check
// that the clocks agree, bag_clocks.h), all before anything is written; then every mapped topic
// in bag order, each message stamped on its topic's clock.
#include <superloc/core/se3.h>
#include <superloc/io/rawlog.h>

#include <algorithm>
#include <map>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "../extras_writer.h"
#include "bag_clocks.h"
#include "bag_source.h"

namespace superloc::io::detail {

std::string canonicalType(const std::string& type) {
    const auto pos = type.find("/msg/");
    return pos == std::string::npos ? type : type.substr(0, pos) + type.substr(pos + 4);
}

namespace {

SE3d toSE3(const PoseFields& p) { return makePose(p.x, p.y, p.z, p.qx, p.qy, p.qz, p.qw); }

/// The static transform tree: T_parent_child per child; T_a_b through the common root.
class StaticTf {
 public:
    void add(const std::string& parent, const std::string& child, const SE3d& T_parent_child) {
        edges_[strip(child)] = {strip(parent), T_parent_child};
    }

    std::optional<SE3d> lookup(const std::string& a, const std::string& b) const {
        if (strip(a) == strip(b)) return SE3d::Identity();
        std::string ra, rb;
        const SE3d T_ra_a = toRoot(strip(a), ra), T_rb_b = toRoot(strip(b), rb);
        if (ra != rb) return std::nullopt;
        return T_ra_a.inverse() * T_rb_b;
    }

 private:
    static std::string strip(const std::string& f) {  // tf2 frame ids carry no leading '/'
        return !f.empty() && f[0] == '/' ? f.substr(1) : f;
    }
    SE3d toRoot(std::string f, std::string& root) const {
        SE3d T = SE3d::Identity();
        for (size_t depth = 0; depth < 100; ++depth) {
            const auto it = edges_.find(f);
            if (it == edges_.end()) break;
            T = it->second.second * T;
            f = it->second.first;
        }
        root = f;
        return T;
    }
    std::map<std::string, std::pair<std::string, SE3d>> edges_;
};

struct Topics {
    std::map<std::string, BagTopic> all;

    /// The topic for `key`: auto-selected among `types` when `value` is empty, none for "none".
    std::string resolve(const std::string& bag, const std::string& key, const std::string& value,
                        const std::vector<std::string>& types) const {
        const auto typeOk = [&](const std::string& t) {
            return std::find(types.begin(), types.end(), canonicalType(t)) != types.end();
        };
        std::string want;
        for (const auto& t : types) want += (want.empty() ? "" : " or ") + t;
        if (value == "none") return "";
        if (value.empty()) {
            std::vector<std::string> found;
            for (const auto& [name, t] : all)
                if (typeOk(t.type)) found.push_back(name);
            if (found.size() > 1) {
                std::string names;
                for (const auto& f : found) names += " " + f;
                throw std::runtime_error(bag + ": several " + want + " topics (" + names.substr(1) +
                                         "): choose one with [rosbag] " + key);
            }
            return found.empty() ? "" : found[0];
        }
        const auto it = all.find(value);
        if (it == all.end())
            throw std::runtime_error(bag + ": topic '" + value + "' ([rosbag] " + key +
                                     ") is not in the bag (see --list)");
        if (!typeOk(it->second.type))
            throw std::runtime_error(bag + ": topic '" + value + "' ([rosbag] " + key + ") is " +
                                     it->second.type + ", expected " + want);
        return value;
    }
};

/// Runs a decoder of `m`; its error becomes one line naming the bag, the topic and the time.
template <class F>
auto decode(const BagMessage& m, const std::string& bag, F&& f) -> decltype(f()) {
    try {
        return f();
    } catch (const std::exception& e) {
        throw std::runtime_error(bag + ": topic '" + m.topic() + "': message at bag time " +
                                 std::to_string(m.bagTime()) + " cannot be decoded: " + e.what());
    }
}

/// Skips (and counts) a message whose stamp does not increase on its topic.
class Monotonic {
 public:
    bool accept(const std::string& topic, double t) {
        auto [it, fresh] = last_.emplace(topic, t);
        if (fresh) return true;
        if (t <= it->second) {
            ++skipped_[topic];
            return false;
        }
        it->second = t;
        return true;
    }
    std::vector<std::pair<std::string, size_t>> skipped() const {
        return {skipped_.begin(), skipped_.end()};
    }

 private:
    std::map<std::string, double> last_;
    std::map<std::string, size_t> skipped_;
};

/// The header of a PointCloud2, Imu, Odometry or PoseStamped message.
MsgHeader headerOf(const BagMessage& m, const std::string& bag) {
    const std::string type = canonicalType(m.type());
    return decode(m, bag, [&] {
        if (type == kPointCloud2) return m.pointCloud2().header;
        if (type == kImu) return m.imu().header;
        return type == kPoseStamped ? m.poseStamped().header : m.odometry().header;
    });
}

SE3d parseExtrinsic(const std::string& s) {
    std::istringstream ss(s);
    double v[7];
    for (double& x : v) ss >> x;
    return makePose(v[0], v[1], v[2], v[3], v[4], v[5], v[6]);
}

Mat6d covFromRos(const std::array<double, 36>& c) {
    Mat6d m;
    for (int r = 0; r < 6; ++r)
        for (int k = 0; k < 6; ++k) m(r, k) = c[size_t(r * 6 + k)];
    return m;
}

}  // namespace

std::vector<BagTopic> listBag(BagSource& bag) { return bag.topics(); }

RosbagImportResult importBag(BagSource& b, const RosbagParams& p, const std::string& out_rawlog,
                             const ProgressFn& progress, const ImportExtras& extras) {
    p.validate();
    const std::string& bag = b.path();
    Topics topics;
    for (auto& t : b.topics()) topics.all[t.topic] = t;
    RosbagImportResult r;
    r.lidar_topic = topics.resolve(bag, "lidar_topic", p.lidar_topic, {kPointCloud2});
    if (r.lidar_topic.empty())
        throw std::runtime_error(bag + ": no " + std::string(kPointCloud2) +
                                 " topic to import ([rosbag] lidar_topic; see --list)");
    r.imu_topic = topics.resolve(bag, "imu_topic", p.imu_topic, {kImu});
    const std::string odom_topic = topics.resolve(
        bag, "odom_alt_topic", p.odom_alt_topic.empty() ? "none" : p.odom_alt_topic, {kOdometry});
    const std::string gt_topic = topics.resolve(
        bag, "gt_topic", p.gt_topic.empty() ? "none" : p.gt_topic, {kOdometry, kPoseStamped});
    std::string tf_topic;
    if (topics.all.count(p.tf_static_topic))
        tf_topic = topics.resolve(bag, "tf_static_topic", p.tf_static_topic, {kTfMessage});

    // Pass 1: static transforms, and the header and record time of every mapped message.
    std::vector<std::string> wanted{r.lidar_topic};
    for (const std::string* t : {&std::as_const(r.imu_topic), &odom_topic, &gt_topic})
        if (!t->empty()) wanted.push_back(*t);
    std::map<std::string, TopicClock> clocks;
    std::map<std::string, std::string> frame_of;  // header.frame_id of a topic's first message
    for (const auto& t : wanted) clocks.emplace(t, TopicClock(t));
    StaticTf tf;
    std::vector<std::string> pass1 = wanted;
    if (!tf_topic.empty()) pass1.push_back(tf_topic);
    b.forEach(pass1, [&](const BagMessage& m) {
        if (m.topic() == tf_topic) {
            for (const auto& x : decode(m, bag, [&] { return m.tfMessage(); }))
                tf.add(x.parent, x.child, toSE3(x.T_parent_child));
            return true;
        }
        const MsgHeader h = headerOf(m, bag);
        TopicClock& c = clocks.at(m.topic());
        if (c.messages() == 0) frame_of[m.topic()] = h.frame_id;
        c.add(h.stamp, m.bagTime());
        return true;
    });
    for (const auto& t : wanted) {
        TopicClock& c = clocks.at(t);
        c.decide(p.stamp_source);
        r.stamps.push_back({t, c.recordTime(), c.reason()});
        if (t != r.lidar_topic) checkClocks(bag, clocks.at(r.lidar_topic), c, p.max_clock_offset);
    }

    // Frames. An empty frame_id is an unknown frame: fine where no transform is needed (a body
    // that is the LiDAR's own frame), an error naming the topic where one is, as a missing
    // transform is.
    const std::string lidar_frame = frame_of[r.lidar_topic];
    const std::string imu_frame = r.imu_topic.empty() ? "" : frame_of[r.imu_topic];
    if (!r.imu_topic.empty() && clocks.at(r.imu_topic).messages() > 0 && imu_frame.empty() &&
        p.body_frame.empty())
        throw std::runtime_error(bag + ": topic '" + r.imu_topic +
                                 "': empty header.frame_id, so the body (IMU) frame is unknown "
                                 "(set [rosbag] body_frame to the frame the IMU measures in)");
    const std::string body = !p.body_frame.empty() ? p.body_frame
                             : !imu_frame.empty()  ? imu_frame
                                                   : lidar_frame;
    if (!imu_frame.empty() && imu_frame != body)
        throw std::runtime_error(bag + ": topic '" + r.imu_topic + "': IMU frame '" + imu_frame +
                                 "' is not the body frame '" + body +
                                 "' ([rosbag] body_frame; IMU samples are not rotated)");
    SE3d T_body_lidar;
    if (!p.lidar_extrinsic.empty()) {
        T_body_lidar = parseExtrinsic(p.lidar_extrinsic);
    } else if (lidar_frame.empty() && !body.empty()) {
        throw std::runtime_error(bag + ": topic '" + r.lidar_topic +
                                 "': empty header.frame_id, so no static transform from '" + body +
                                 "' to the LiDAR can be looked up (set [rosbag] lidar_extrinsic)");
    } else if (auto T = tf.lookup(body, lidar_frame)) {
        T_body_lidar = *T;
    } else {
        throw std::runtime_error(bag + ": no static transform from '" + body + "' to '" +
                                 lidar_frame + "' on '" + p.tf_static_topic +
                                 "' (set [rosbag] lidar_extrinsic)");
    }
    // T_child_lidar (gt) and T_child_body (odom_alt) for a pose message's child frame.
    const auto childTo = [&](const std::string& topic, const std::string& child, bool to_lidar) {
        const auto T_child_body = tf.lookup(child, body);
        if (T_child_body) return to_lidar ? SE3d(*T_child_body * T_body_lidar) : *T_child_body;
        if (to_lidar && !lidar_frame.empty())
            if (auto T = tf.lookup(child, lidar_frame)) return *T;
        if (body.empty())  // the body is the LiDAR's frame, and its messages name none
            throw std::runtime_error(bag + ": topic '" + topic +
                                     "': no static transform from its child frame '" + child +
                                     "' to the LiDAR: topic '" + r.lidar_topic +
                                     "' has an empty header.frame_id (set [rosbag] body_frame "
                                     "and lidar_extrinsic)");
        throw std::runtime_error(bag + ": topic '" + topic +
                                 "': no static transform from its "
                                 "child frame '" +
                                 child + "' to '" + (to_lidar ? lidar_frame : body) + "'");
    };
    std::map<std::string, SE3d> child_cache;
    const auto cachedChild = [&](const std::string& topic, const std::string& child,
                                 bool to_lidar) -> const SE3d& {
        const std::string key = topic + "|" + child;
        auto it = child_cache.find(key);
        if (it == child_cache.end())
            it = child_cache.emplace(key, childTo(topic, child, to_lidar)).first;
        return it->second;
    };

    // Pass 2: every mapped topic in bag order.
    const size_t n_scans = topics.all.at(r.lidar_topic).messages;
    const PointTimeOptions topt{p.point_time_field, p.point_time_unit, p.point_time_reference};
    Monotonic mono;
    RawlogWriter w(out_rawlog);
    ExtrasWriter ex(extras, r);
    b.forEach(wanted, [&](const BagMessage& m) {
        const std::string& topic = m.topic();
        const TopicClock& clock = clocks.at(topic);
        if (topic == r.lidar_topic) {
            PointCloud2Msg pc = decode(m, bag, [&] { return m.pointCloud2(); });
            const double t = clock.stamp(pc.header.stamp, m.bagTime());
            if (!mono.accept(topic, t)) return true;
            ex.flushUntil(w, t);
            // Per-point times are relative to header.stamp or absolute near it; a scan on the
            // record time with the stamp unset reads them against the record time. The scan
            // keeps them relative to its own time `t`.
            if (clock.recordTime() && pc.header.stamp == 0) pc.cloud.stamp = m.bagTime();
            Scan s;
            PointCloud2Stats st;
            try {
                st = decodePointCloud2(pc.cloud, topt, s);
                s.t = t;
            } catch (const std::exception& e) {
                throw std::runtime_error(bag + ": topic '" + topic + "': scan at " +
                                         std::to_string(t) + ": " + e.what());
            }
            s.T_imu_lidar = T_body_lidar;
            r.dropped_points += st.invalid_points;
            if (s.empty()) {
                if (r.empty_scans++ == 0) r.first_empty = "'" + topic + "' at t=" + std::to_string(t);
                return true;
            }
            if (!s.rel_time.empty()) {
                w.writeTimedScan(s, p.lidar_label, float(p.intensity_max));
                if (r.time_field.empty()) r.time_field = st.time_field;
                ++r.timed_scans;
            } else {
                w.writeScan(s, p.lidar_label);
            }
            ++r.scans;
            r.points += s.size();
            if (progress) progress(std::min(r.scans, n_scans), n_scans);
        } else if (topic == r.imu_topic) {
            const ImuMsg imu = decode(m, bag, [&] { return m.imu(); });
            ImuSample s;
            s.t = clock.stamp(imu.header.stamp, m.bagTime());
            if (!mono.accept(topic, s.t)) return true;
            s.acc = imu.linear_acceleration;
            s.gyro = imu.angular_velocity;
            w.writeImu(s, p.imu_label);
            ++r.imu;
        } else {
            // Odometry (odom_alt or gt) or PoseStamped (gt).
            const bool is_gt = topic == gt_topic;
            const bool stamped = canonicalType(m.type()) == kPoseStamped;
            const PoseMsg msg =
                decode(m, bag, [&] { return stamped ? m.poseStamped() : m.odometry(); });
            PoseStamped ps;
            ps.t = clock.stamp(msg.header.stamp, m.bagTime());
            const SE3d T_parent_child = toSE3(msg.pose);
            std::string child;
            if (stamped)
                child = p.gt_child_frame.empty() ? body : p.gt_child_frame;
            else
                child = msg.child_frame_id.empty() ? body : msg.child_frame_id;
            if (msg.covariance) ps.cov = covFromRos(*msg.covariance);
            if (!mono.accept(topic, ps.t)) return true;
            // gt: T_map_lidar; odom_alt: T_odom_body (doc/io.md).
            ps.pose = T_parent_child * cachedChild(topic, child, is_gt);
            w.writePose(ps, is_gt ? p.gt_label : p.odom_alt_label);
            ++(is_gt ? r.gt_poses : r.odom_alt);
        }
        return true;
    });
    ex.flushAll(w);
    w.close();
    r.non_monotonic = mono.skipped();
    return r;
}

}  // namespace superloc::io::detail
