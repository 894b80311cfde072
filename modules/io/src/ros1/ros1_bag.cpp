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

#include <fstream>
#include <functional>
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
        for (const auto& f : pc->fields)
            v.fields.push_back({f.name, f.offset, f.datatype, f.count});
        v.data = pc->data.data();
        v.data_size = pc->data.size();
        return out;
    }
    ImuMsg imu() const override {
        const auto m = instantiate<sensor_msgs::Imu>();
        ImuMsg out;
        out.header = header(m->header);
        out.angular_velocity = {m->angular_velocity.x, m->angular_velocity.y,
                                m->angular_velocity.z};
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
            out.push_back(
                {x.header.frame_id, x.child_frame_id, {t.x, t.y, t.z, q.x, q.y, q.z, q.w}});
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

/// rosbag_storage trusts the lengths in the file: a record header length of 2 GB makes it
/// allocate 2 GB, an index position inside a record makes it read any bytes as a header (both
/// found by fuzz_ros1). So the top level of the file (ROS bag format 2.0: after
/// "#ROSBAG V2.0\n", records of int32 header length, header fields "int32 length, name=value",
/// int32 data length, data) is walked first: every length must fit in the file, the bag header's
/// index_pos and every chunk info's chunk_pos must point at a record, and a chunk's uncompressed
/// `size` must be plausible (equal to its data length when stored uncompressed, whose inner
/// records are walked the same way). Throws "<bag>: corrupt ROS 1 bag: ..." naming the byte.
void checkRos1Structure(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    in.seekg(0, std::ios::end);
    const size_t file_size = size_t(in.tellg());
    const auto fail = [&](size_t at, const std::string& why) {
        throw std::runtime_error(path + ": corrupt ROS 1 bag: record at byte " +
                                 std::to_string(at) + ": " + why);
    };
    const auto u32 = [](const std::vector<uint8_t>& b, size_t at) {
        return uint32_t(b[at]) | uint32_t(b[at + 1]) << 8 | uint32_t(b[at + 2]) << 16 |
               uint32_t(b[at + 3]) << 24;
    };
    struct Record {
        size_t at;
        std::map<std::string, std::string> fields;
        size_t data_at, data_len;
    };
    // The records of [begin, end) of a byte source get(pos, n), each checked to lie inside it;
    // only headers are read (and the data of uncompressed chunks, walked the same way).
    using Get = std::function<std::vector<uint8_t>(size_t, size_t)>;
    const auto walk = [&](size_t begin, size_t end, const Get& get) {
        std::vector<Record> recs;
        for (size_t at = begin; at < end;) {
            if (end - at < 4) fail(at, "no room for a header length");
            const size_t hlen = u32(get(at, 4), 0);
            if (hlen > end - at - 4)
                fail(at, "header length " + std::to_string(hlen) + " runs past the end");
            const auto h = get(at + 4, hlen);
            Record r{at, {}, 0, 0};
            for (size_t f = 0; f < hlen;) {
                if (hlen - f < 4) fail(at, "header field without room for its length");
                const size_t flen = u32(h, f);
                if (flen > hlen - f - 4) fail(at, "header field runs past the header");
                const std::string kv(reinterpret_cast<const char*>(h.data() + f + 4), flen);
                const auto eq = kv.find('=');
                if (eq != std::string::npos) r.fields[kv.substr(0, eq)] = kv.substr(eq + 1);
                f += 4 + flen;
            }
            const size_t d = at + 4 + hlen;
            if (end - d < 4) fail(at, "no room for the data length");
            r.data_len = u32(get(d, 4), 0);
            r.data_at = d + 4;
            if (r.data_len > end - r.data_at)
                fail(at, "data length " + std::to_string(r.data_len) + " runs past the end");
            at = r.data_at + r.data_len;
            recs.push_back(std::move(r));
        }
        return recs;
    };
    const Get from_file = [&](size_t pos, size_t n) {
        std::vector<uint8_t> b(n);
        in.clear();
        in.seekg(std::streamoff(pos));
        in.read(reinterpret_cast<char*>(b.data()), std::streamsize(n));
        if (!in) fail(pos, "cannot read " + std::to_string(n) + " bytes");
        return b;
    };
    const auto num = [](const std::string& v) {
        uint64_t x = 0;
        for (size_t i = 0; i < v.size() && i < 8; ++i) x |= uint64_t(uint8_t(v[i])) << (8 * i);
        return x;
    };
    if (file_size < 13) fail(0, "shorter than the format line");
    const auto recs = walk(13, file_size, from_file);
    std::map<size_t, const Record*> at;
    for (const auto& r : recs) at[r.at] = &r;
    for (const auto& r : recs) {
        const auto op = r.fields.find("op");
        if (op == r.fields.end() || op->second.size() != 1) fail(r.at, "no 'op' field");
        const uint8_t code = uint8_t(op->second[0]);
        if (code == 0x03 && r.fields.count("index_pos")) {  // bag header
            const uint64_t pos = num(r.fields.at("index_pos"));
            if (pos != 0 && !at.count(size_t(pos)))
                fail(r.at, "index_pos " + std::to_string(pos) + " is not a record");
        } else if (code == 0x06 && r.fields.count("chunk_pos")) {  // chunk info
            const uint64_t pos = num(r.fields.at("chunk_pos"));
            const auto it = at.find(size_t(pos));
            if (it == at.end() || it->second->fields.count("op") == 0 ||
                it->second->fields.at("op") != std::string(1, '\x05'))
                fail(r.at, "chunk_pos " + std::to_string(pos) + " is not a chunk record");
        } else if (code == 0x05) {  // chunk
            const auto c = r.fields.find("compression");
            const auto size = r.fields.find("size");
            if (c == r.fields.end() || size == r.fields.end())
                fail(r.at, "chunk without compression/size");
            const uint64_t usize = num(size->second);
            if (c->second == "none") {
                if (usize != r.data_len)
                    fail(r.at, "uncompressed chunk size " + std::to_string(usize) +
                                   " is not its data length " + std::to_string(r.data_len));
                const auto data = from_file(r.data_at, r.data_len);
                walk(0, data.size(), [&](size_t pos, size_t n) {
                    return std::vector<uint8_t>(data.begin() + long(pos),
                                                data.begin() + long(pos + n));
                });
            } else if (usize > (uint64_t(1) << 30) ||
                       usize > uint64_t(r.data_len) * 4096 + (1 << 20)) {
                fail(r.at, "implausible uncompressed chunk size " + std::to_string(usize));
            }
        }
    }
}

class Ros1Bag : public BagSource {
 public:
    explicit Ros1Bag(const std::string& path) : path_(path) {
        checkRos1Structure(path);
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
