// Which clock stamps a bag topic, and whether two topics' clocks agree (bag_clocks.h).
#include "bag_clocks.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>
#include <stdexcept>

namespace superloc::io::detail {

namespace {

std::string fixed3(double v) {
    std::ostringstream s;
    s << std::fixed << std::setprecision(3) << v;
    return s.str();
}

std::string ofMessages(size_t k, size_t n) {
    return std::to_string(k) + " of " + std::to_string(n) + " messages";
}

}  // namespace

void TopicClock::add(double header_stamp, double record_time) {
    if (n_ == 0) {
        hdr_min_ = hdr_max_ = hdr_last_ = header_stamp;
        rec_min_ = rec_max_ = record_time;
    } else {
        hdr_min_ = std::min(hdr_min_, header_stamp);
        hdr_max_ = std::max(hdr_max_, header_stamp);
        rec_min_ = std::min(rec_min_, record_time);
        rec_max_ = std::max(rec_max_, record_time);
        // The same rule as the import's: a stamp counts when it exceeds the last one kept.
        if (header_stamp <= hdr_last_)
            ++not_increasing_;
        else
            hdr_last_ = header_stamp;
    }
    if (header_stamp == 0) ++zero_;
    hdr_minus_rec_.push_back(header_stamp - record_time);
    ++n_;
}

void TopicClock::decide(const std::string& stamp_source) {
    reason_.clear();
    if (stamp_source == "auto" && zero_ > 0)
        reason_ = "header.stamp is 0 on " + ofMessages(zero_, n_);
    // A rare repeated stamp (a driver's rounding) is better skipped than trading the whole
    // topic's stamps for the record time and its transport latency; many are not.
    else if (stamp_source == "auto" && not_increasing_ * 100 > n_)
        reason_ = "header.stamp does not increase on " + ofMessages(not_increasing_, n_);
    record_ = stamp_source == "record" || !reason_.empty();
    offset_ = 0;
    if (!record_ && !hdr_minus_rec_.empty()) {
        std::vector<double> d = hdr_minus_rec_;
        std::nth_element(d.begin(), d.begin() + long(d.size() / 2), d.end());
        offset_ = d[d.size() / 2];
    }
}

void checkClocks(const std::string& bag, const TopicClock& lidar, const TopicClock& other,
                 double max_offset) {
    if (!(max_offset > 0) || lidar.messages() == 0 || other.messages() == 0) return;
    const double diff = std::abs(lidar.offsetToRecord() - other.offsetToRecord());
    const bool overlap = other.first() <= lidar.last() && lidar.first() <= other.last();
    if (overlap && diff <= max_offset) return;
    const auto describe = [](const TopicClock& c) {
        return "topic '" + c.topic() + "' (" + c.clockName() + ", " + fixed3(c.first()) + " to " +
               fixed3(c.last()) + " s)";
    };
    std::ostringstream limit;
    limit << max_offset;
    const bool both_record = lidar.recordTime() && other.recordTime();
    std::string what = "the times of " + describe(lidar) + " and " + describe(other);
    if (!overlap)
        what += " do not overlap";
    else
        what += " overlap, but";
    if (!both_record)
        what += std::string(overlap ? "" : " and") + " their clocks differ by " + fixed3(diff) +
                " s against the bag's record time";
    if (overlap) what += " (more than [rosbag] max_clock_offset = " + limit.str() + " s)";
    throw std::runtime_error(bag + ": " + what + ": set [rosbag] " +
                             (both_record ? "" : "stamp_source = record to stamp both with it, or ") +
                             "max_clock_offset = 0 to import anyway");
}

}  // namespace superloc::io::detail
