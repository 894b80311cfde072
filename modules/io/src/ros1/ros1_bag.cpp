// ROS 1 bag reader through Debian's rosbag_storage and the sensor_msgs / nav_msgs /
// geometry_msgs / tf2_msgs C++ message headers (library superloc::io_ros1): the BagSource of
// bag/bag_source.h. What the messages become is decided in bag/bag_import.cpp, shared with the
// ROS 2 readers.
#include <geometry_msgs/PoseStamped.h>
#include <nav_msgs/Odometry.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/PointCloud2.h>
#include <tf2_msgs/TFMessage.h>

#include <map>
#include <stdexcept>

#include "../bag/bag_source.h"

namespace superloc::io::detail {

namespace {

MsgHeader header(const std_msgs::Header& h) {
    return {double(h.stamp.sec) + double(h.stamp.nsec) * 1e-9, h.frame_id};
}

PoseFields pose(const geometry_msgs::Point& p, const geometry_msgs::Quaternion& q) {
    return {p.x, p.y, p.z, q.x, q.y, q.z, q.w};
}

class Ros1Message : public BagMessage {
 public:
    explicit Ros1Message(const rosbag::MessageInstance& m)
        : m_(m), topic_(m.getTopic()), type_(m.getDataType()) {}
    const std::string& topic() const override { return topic_; }
    const std::string& type() const override { return type_; }
    double bagTime() const override { return m_.getTime().toSec(); }

    PointCloud2Msg pointCloud2() const override {
        const auto pc = instantiate<sensor_msgs::PointCloud2>();
        keep_ = pc;  // cloud.data points into it
        PointCloud2Msg out;
        out.header = header(pc->header);
        PointCloud2View& v = out.cloud;
        v.stamp = out.header.stamp;
        v.height = pc->height;
        v.width = pc->width;
        v.point_step = pc->point_step;
        v.row_step = pc->row_step;
        v.is_bigendian = pc->is_bigendian;
        for (const auto& f : pc->fields) v.fields.push_back({f.name, f.offset, f.datatype, f.count});
        v.data = pc->data.data();
        v.data_size = pc->data.size();
        return out;
    }
    ImuMsg imu() const override {
        const auto m = instantiate<sensor_msgs::Imu>();
        ImuMsg out;
        out.header = header(m->header);
        out.angular_velocity = {m->angular_velocity.x, m->angular_velocity.y, m->angular_velocity.z};
        out.linear_acceleration = {m->linear_acceleration.x, m->linear_acceleration.y,
                                   m->linear_acceleration.z};
        return out;
    }
    PoseMsg odometry() const override {
        const auto m = instantiate<nav_msgs::Odometry>();
        PoseMsg out;
        out.header = header(m->header);
        out.child_frame_id = m->child_frame_id;
        out.pose = pose(m->pose.pose.position, m->pose.pose.orientation);
        out.covariance.emplace();
        std::copy(m->pose.covariance.begin(), m->pose.covariance.end(), out.covariance->begin());
        return out;
    }
    PoseMsg poseStamped() const override {
        const auto m = instantiate<geometry_msgs::PoseStamped>();
        PoseMsg out;
        out.header = header(m->header);
        out.pose = pose(m->pose.position, m->pose.orientation);
        return out;
    }
    std::vector<TransformMsg> tfMessage() const override {
        std::vector<TransformMsg> out;
        // Hold the message: a range-for over `instantiate<>()->transforms` would iterate a
        // vector freed with its temporary shared_ptr (found by fuzz_ros1 on its seeds).
        const auto msg = instantiate<tf2_msgs::TFMessage>();
        for (const auto& x : msg->transforms) {
            const auto& t = x.transform.translation;
            const auto& q = x.transform.rotation;
            out.push_back({x.header.frame_id, x.child_frame_id,
                           {t.x, t.y, t.z, q.x, q.y, q.z, q.w}});
        }
        return out;
    }

 private:
    template <class Msg>
    boost::shared_ptr<Msg> instantiate() const {
        auto p = m_.instantiate<Msg>();
        if (!p)
            throw std::runtime_error("holds " + type_ + ", which does not decode as " +
                                     ros::message_traits::DataType<Msg>::value());
        return p;
    }
    const rosbag::MessageInstance& m_;
    std::string topic_, type_;
    mutable boost::shared_ptr<const void> keep_;
};

class Ros1Bag : public BagSource {
 public:
    explicit Ros1Bag(const std::string& path) : path_(path) {
        try {
            bag_.open(path, rosbag::bagmode::Read);
        } catch (const std::exception& e) {
            throw std::runtime_error(path + ": cannot read ROS 1 bag: " + e.what());
        }
    }
    const std::string& path() const override { return path_; }

    std::vector<BagTopic> topics() override {
        std::map<std::string, BagTopic> all;
        try {
            rosbag::View v(bag_);
            for (const rosbag::ConnectionInfo* c : v.getConnections()) {
                auto& bt = all[c->topic];
                bt.topic = c->topic;
                bt.type = c->datatype;
            }
            for (auto& [name, bt] : all)
                bt.messages = rosbag::View(bag_, rosbag::TopicQuery(name)).size();
        } catch (const std::exception& e) {
            throw std::runtime_error(path_ + ": cannot read ROS 1 bag index: " + e.what());
        }
        std::vector<BagTopic> out;
        for (auto& [name, t] : all) out.push_back(t);
        return out;
    }

    void forEach(const std::vector<std::string>& topics,
                 const std::function<bool(const BagMessage&)>& fn) override {
        try {
            for (const rosbag::MessageInstance& m : rosbag::View(bag_, rosbag::TopicQuery(topics)))
                if (!fn(Ros1Message(m))) break;
        } catch (const rosbag::BagException& e) {
            throw std::runtime_error(path_ + ": corrupt or truncated ROS 1 bag: " + e.what());
        }
    }

 private:
    std::string path_;
    rosbag::Bag bag_;
};

}  // namespace

std::unique_ptr<BagSource> openRos1Bag(const std::string& path) {
    return std::make_unique<Ros1Bag>(path);
}

}  // namespace superloc::io::detail
