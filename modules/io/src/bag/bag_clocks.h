// Private to io: which clock stamps each imported bag topic ([rosbag] stamp_source) and whether
// the topics' clocks agree ([rosbag] max_clock_offset). bag_import.cpp surveys every message's
// header.stamp and record time before it writes anything (TopicClock::add), decides the clock
// per topic (decide), checks the LiDAR's clock against every other imported topic's
// (checkClocks), then stamps each message with TopicClock::stamp. doc/your-data.md, section 2.
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace superloc::io::detail {

/// The stamps of one topic: its header.stamp and the bag's record (receive) time per message.
/// "Record time" is the ROS 1 connection time of the message, rosbag2's `timestamp` column and
/// MCAP's `log_time`: when the recorder received it, on the recording machine's clock.
class TopicClock {
 public:
    explicit TopicClock(std::string topic) : topic_(std::move(topic)) {}

    /// One message, in bag order: its header.stamp and record time [s].
    void add(double header_stamp, double record_time);
    /// Chooses the clock for `stamp_source` (after every add): header, record, or auto = the
    /// record time when header.stamp is 0 (unset) on any message or does not increase on more
    /// than 1% of them, else header.stamp.
    void decide(const std::string& stamp_source);

    /// The time of a message on the chosen clock.
    double stamp(double header_stamp, double record_time) const {
        return record_ ? record_time : header_stamp;
    }
    const std::string& topic() const { return topic_; }
    bool recordTime() const { return record_; }
    /// Why auto chose the record time (e.g. "header.stamp is 0 on 412 of 412 messages"), else "".
    const std::string& reason() const { return reason_; }
    std::string clockName() const { return record_ ? "record time" : "header.stamp"; }
    size_t messages() const { return n_; }
    /// First and last time on the chosen clock [s] (messages() > 0).
    double first() const { return record_ ? rec_min_ : hdr_min_; }
    double last() const { return record_ ? rec_max_ : hdr_max_; }
    /// Median of (chosen clock - record time) [s]: how far this topic's clock is from the bag's.
    double offsetToRecord() const { return offset_; }

 private:
    std::string topic_;
    size_t n_ = 0, zero_ = 0;
    double hdr_min_ = 0, hdr_max_ = 0, rec_min_ = 0, rec_max_ = 0;
    double hdr_last_ = 0;        ///< last increasing header.stamp
    size_t not_increasing_ = 0;  ///< messages whose header.stamp did not increase
    std::vector<double> hdr_minus_rec_;
    bool record_ = false;
    double offset_ = 0;
    std::string reason_;
};

/// Throws std::runtime_error, one line naming `bag` and both topics with their clocks and
/// ranges, when the times of `lidar` and `other` do not overlap, or when their clocks differ by
/// more than `max_offset` [s] relative to the bag's record time. max_offset = 0: no check; a
/// topic without messages is not checked.
void checkClocks(const std::string& bag, const TopicClock& lidar, const TopicClock& other,
                 double max_offset);

}  // namespace superloc::io::detail
