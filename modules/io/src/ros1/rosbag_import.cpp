// ROS 1 bag -> rawlog through Debian's rosbag_storage and the sensor_msgs / nav_msgs /
// geometry_msgs / tf2_msgs C++ message headers (library superloc::io_ros1). Two passes: the
// static transforms first (they may be recorded after the first scans), then every mapped topic
// in bag order, each message stamped with its header.stamp. See superloc/io/rosbag.h.
#include <geometry_msgs/PoseStamped.h>
#include <nav_msgs/Odometry.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/PointCloud2.h>
#include <superloc/core/se3.h>
#include <superloc/io/rawlog.h>
#include <superloc/io/rosbag.h>
#include <tf2_msgs/TFMessage.h>

#include <algorithm>
#include <map>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "../extras_writer.h"
#include "../pointcloud2.h"

namespace superloc::io {

namespace {

constexpr const char* kPointCloud2 = "sensor_msgs/PointCloud2";
constexpr const char* kImu = "sensor_msgs/Imu";
constexpr const char* kOdometry = "nav_msgs/Odometry";
constexpr const char* kPoseStamped = "geometry_msgs/PoseStamped";
constexpr const char* kTfMessage = "tf2_msgs/TFMessage";

double toSec(const ros::Time& t) { return double(t.sec) + double(t.nsec) * 1e-9; }

SE3d toSE3(const geometry_msgs::Point& p, const geometry_msgs::Quaternion& q) {
    return makePose(p.x, p.y, p.z, q.x, q.y, q.z, q.w);
}

/// The static transform tree: T_parent_child per child; T_a_b through the common root.
class StaticTf {
 public:
    void add(const std::string& parent, const std::string& child, const SE3d& T_parent_child) {
        edges_[strip(child)] = {strip(parent), T_parent_child};
    }
    bool empty() const { return edges_.empty(); }

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
            return std::find(types.begin(), types.end(), t) != types.end();
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

Topics readTopics(rosbag::Bag& b) {
    Topics t;
    rosbag::View v(b);
    for (const rosbag::ConnectionInfo* c : v.getConnections()) {
        auto& bt = t.all[c->topic];
        bt.topic = c->topic;
        bt.type = c->datatype;
    }
    for (auto& [name, bt] : t.all) bt.messages = rosbag::View(b, rosbag::TopicQuery(name)).size();
    return t;
}

void openBag(rosbag::Bag& b, const std::string& path) {
    try {
        b.open(path, rosbag::bagmode::Read);
    } catch (const std::exception& e) {
        throw std::runtime_error(path + ": cannot read ROS 1 bag: " + e.what());
    }
}

template <class Msg>
boost::shared_ptr<Msg> instantiate(const rosbag::MessageInstance& m, const std::string& bag) {
    boost::shared_ptr<Msg> p;
    try {
        p = m.instantiate<Msg>();
    } catch (const std::exception& e) {
        throw std::runtime_error(bag + ": topic '" + m.getTopic() + "': message at bag time " +
                                 std::to_string(m.getTime().toSec()) +
                                 " cannot be decoded: " + e.what());
    }
    if (!p)
        throw std::runtime_error(bag + ": topic '" + m.getTopic() + "' holds " + m.getDataType() +
                                 ", which does not decode as " +
                                 ros::message_traits::DataType<Msg>::value());
    return p;
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

SE3d parseExtrinsic(const std::string& s) {
    std::istringstream ss(s);
    double v[7];
    for (double& x : v) ss >> x;
    return makePose(v[0], v[1], v[2], v[3], v[4], v[5], v[6]);
}

Mat6d covFromRos(const boost::array<double, 36>& c) {
    Mat6d m;
    for (int r = 0; r < 6; ++r)
        for (int k = 0; k < 6; ++k) m(r, k) = c[size_t(r * 6 + k)];
    return m;
}

}  // namespace

std::vector<BagTopic> listRosbag(const std::string& bag) {
    rosbag::Bag b;
    openBag(b, bag);
    std::vector<BagTopic> out;
    try {
        for (const auto& [name, t] : readTopics(b).all) out.push_back(t);
    } catch (const std::exception& e) {
        throw std::runtime_error(bag + ": cannot read ROS 1 bag index: " + e.what());
    }
    return out;
}

RosbagImportResult importRosbag(const std::string& bag, const RosbagParams& p,
                                const std::string& out_rawlog, const ProgressFn& progress,
                                const ImportExtras& extras) {
    p.validate();
    rosbag::Bag b;
    openBag(b, bag);
    const Topics topics = readTopics(b);
    RosbagImportResult r;
    r.lidar_topic = topics.resolve(bag, "lidar_topic", p.lidar_topic, {kPointCloud2});
    if (r.lidar_topic.empty())
        throw std::runtime_error(bag + ": no " + std::string(kPointCloud2) +
                                 " topic to import ([rosbag] lidar_topic; see --list)");
    r.imu_topic = topics.resolve(bag, "imu_topic", p.imu_topic, {kImu});
    const std::string odom_topic =
        topics.resolve(bag, "odom_alt_topic", p.odom_alt_topic.empty() ? "none" : p.odom_alt_topic,
                       {kOdometry});
    const std::string gt_topic = topics.resolve(
        bag, "gt_topic", p.gt_topic.empty() ? "none" : p.gt_topic, {kOdometry, kPoseStamped});
    std::string tf_topic;
    if (topics.all.count(p.tf_static_topic))
        tf_topic = topics.resolve(bag, "tf_static_topic", p.tf_static_topic, {kTfMessage});

    try {
        // Pass 1: static transforms, and the frames of the LiDAR and IMU.
        StaticTf tf;
        if (!tf_topic.empty())
            for (const auto& m : rosbag::View(b, rosbag::TopicQuery(tf_topic))) {
                // Hold the message: a range-for over instantiate(...)->transforms iterates a
                // member of a temporary freed before the loop body (found by ASan).
                const auto msg = instantiate<tf2_msgs::TFMessage>(m, bag);
                for (const auto& x : msg->transforms) {
                    const auto& q = x.transform.rotation;
                    const auto& t = x.transform.translation;
                    tf.add(x.header.frame_id, x.child_frame_id,
                           makePose(t.x, t.y, t.z, q.x, q.y, q.z, q.w));
                }
            }
        const auto firstFrame = [&](const std::string& topic, auto tag) {
            using Msg = typename decltype(tag)::type;
            for (const auto& m : rosbag::View(b, rosbag::TopicQuery(topic)))
                return instantiate<Msg>(m, bag)->header.frame_id;
            return std::string();
        };
        struct PcTag { using type = sensor_msgs::PointCloud2; };
        struct ImuTag { using type = sensor_msgs::Imu; };
        const std::string lidar_frame = firstFrame(r.lidar_topic, PcTag{});
        const std::string imu_frame = r.imu_topic.empty() ? "" : firstFrame(r.imu_topic, ImuTag{});
        const std::string body =
            !p.body_frame.empty() ? p.body_frame : !imu_frame.empty() ? imu_frame : lidar_frame;
        if (!imu_frame.empty() && imu_frame != body)
            throw std::runtime_error(bag + ": topic '" + r.imu_topic + "': IMU frame '" + imu_frame +
                                     "' is not the body frame '" + body +
                                     "' ([rosbag] body_frame; IMU samples are not rotated)");
        SE3d T_body_lidar;
        if (!p.lidar_extrinsic.empty()) {
            T_body_lidar = parseExtrinsic(p.lidar_extrinsic);
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
            if (to_lidar)
                if (auto T = tf.lookup(child, lidar_frame)) return *T;
            throw std::runtime_error(bag + ": topic '" + topic + "': no static transform from its "
                                     "child frame '" + child + "' to '" +
                                     (to_lidar ? lidar_frame : body) + "'");
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
        std::vector<std::string> wanted{r.lidar_topic};
        const std::string& imu_topic = r.imu_topic;
        for (const std::string* t : {&imu_topic, &odom_topic, &gt_topic})
            if (!t->empty()) wanted.push_back(*t);
        rosbag::View view(b, rosbag::TopicQuery(wanted));
        const size_t n_scans = topics.all.at(r.lidar_topic).messages;
        detail::PointTimeOptions topt{p.point_time_field, p.point_time_unit,
                                      p.point_time_reference};
        Monotonic mono;
        RawlogWriter w(out_rawlog);
        detail::ExtrasWriter ex(extras, r);
        for (const rosbag::MessageInstance& m : view) {
            const std::string& topic = m.getTopic();
            if (topic == r.lidar_topic) {
                const auto pc = instantiate<sensor_msgs::PointCloud2>(m, bag);
                const double t = toSec(pc->header.stamp);
                if (!mono.accept(topic, t)) continue;
                ex.flushUntil(w, t);
                detail::PointCloud2View v;
                v.stamp = t;
                v.height = pc->height;
                v.width = pc->width;
                v.point_step = pc->point_step;
                v.row_step = pc->row_step;
                v.is_bigendian = pc->is_bigendian;
                for (const auto& f : pc->fields)
                    v.fields.push_back({f.name, f.offset, f.datatype, f.count});
                v.data = pc->data.data();
                v.data_size = pc->data.size();
                Scan s;
                detail::PointCloud2Stats st;
                try {
                    st = detail::decodePointCloud2(v, topt, s);
                } catch (const std::exception& e) {
                    throw std::runtime_error(bag + ": topic '" + topic + "': scan at " +
                                             std::to_string(t) + ": " + e.what());
                }
                s.T_imu_lidar = T_body_lidar;
                r.dropped_points += st.invalid_points;
                if (s.empty()) continue;
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
                const auto imu = instantiate<sensor_msgs::Imu>(m, bag);
                ImuSample s;
                s.t = toSec(imu->header.stamp);
                if (!mono.accept(topic, s.t)) continue;
                s.acc = {imu->linear_acceleration.x, imu->linear_acceleration.y,
                         imu->linear_acceleration.z};
                s.gyro = {imu->angular_velocity.x, imu->angular_velocity.y,
                          imu->angular_velocity.z};
                w.writeImu(s, p.imu_label);
                ++r.imu;
            } else {
                // Odometry (odom_alt or gt) or PoseStamped (gt).
                const bool is_gt = topic == gt_topic;
                PoseStamped ps;
                std::string child;
                SE3d T_parent_child;
                if (m.getDataType() == kPoseStamped) {
                    const auto msg = instantiate<geometry_msgs::PoseStamped>(m, bag);
                    ps.t = toSec(msg->header.stamp);
                    T_parent_child = toSE3(msg->pose.position, msg->pose.orientation);
                    child = p.gt_child_frame.empty() ? body : p.gt_child_frame;
                } else {
                    const auto msg = instantiate<nav_msgs::Odometry>(m, bag);
                    ps.t = toSec(msg->header.stamp);
                    T_parent_child = toSE3(msg->pose.pose.position, msg->pose.pose.orientation);
                    child = msg->child_frame_id.empty() ? body : msg->child_frame_id;
                    ps.cov = covFromRos(msg->pose.covariance);
                }
                if (!mono.accept(topic, ps.t)) continue;
                // gt: T_map_lidar; odom_alt: T_odom_body (doc/io.md).
                ps.pose = T_parent_child * cachedChild(topic, child, is_gt);
                w.writePose(ps, is_gt ? p.gt_label : p.odom_alt_label);
                ++(is_gt ? r.gt_poses : r.odom_alt);
            }
        }
        ex.flushAll(w);
        w.close();
        r.non_monotonic = mono.skipped();
    } catch (const rosbag::BagException& e) {
        throw std::runtime_error(bag + ": corrupt or truncated ROS 1 bag: " + e.what());
    }
    return r;
}

}  // namespace superloc::io
