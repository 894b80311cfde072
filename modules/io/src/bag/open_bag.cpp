// importRosbag / listRosbag: picks the reader by the file's first bytes (ROS 1 "#ROSBAG V2.0",
// SQLite "SQLite format 3", MCAP "\x89MCAP0\r\n") and hands it to the shared conversion. Library
// superloc::io_bags, which also links the ROS 1 reader when the build has it.
#include <superloc/io/rosbag.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "bag_source.h"

namespace superloc::io {

namespace detail {

#ifndef SUPERLOC_HAVE_ROS1
std::unique_ptr<BagSource> openRos1Bag(const std::string& path) {
    throw std::runtime_error(path +
                             ": a ROS 1 bag, and this build has no ROS 1 bag support "
                             "(install the packages of scripts/install-deps.sh, re-run cmake)");
}
#endif

namespace {

/// A ROS 2 bag folder (metadata.yaml + storage files): its one .db3 or .mcap file.
std::string storageFileOf(const std::string& dir) {
    std::vector<std::string> found;
    for (const auto& e : std::filesystem::directory_iterator(dir)) {
        const auto ext = e.path().extension().string();
        if (e.is_regular_file() && (ext == ".db3" || ext == ".mcap")) found.push_back(e.path());
    }
    if (found.size() != 1)
        throw std::runtime_error(dir + ": a bag folder must hold exactly one .db3 or .mcap file (" +
                                 std::to_string(found.size()) + " found); give the file instead");
    return found[0];
}

}  // namespace

std::unique_ptr<BagSource> openBag(const std::string& path_in) {
    std::error_code ec;
    if (!std::filesystem::exists(path_in, ec))
        throw std::runtime_error(path_in + ": no such bag file");
    const std::string path =
        std::filesystem::is_directory(path_in, ec) ? storageFileOf(path_in) : path_in;
    char magic[16] = {};
    {
        std::ifstream in(path, std::ios::binary);
        if (!in) throw std::runtime_error(path + ": cannot open");
        in.read(magic, sizeof(magic));
    }
    if (std::memcmp(magic, "#ROSBAG V2.0\n", 13) == 0) return openRos1Bag(path);
    if (std::memcmp(magic, "SQLite format 3", 16) == 0) return openDb3Bag(path);
    if (std::memcmp(magic, "\x89MCAP0\r\n", 8) == 0) return openMcapBag(path);
    throw std::runtime_error(path +
                             ": not a bag (neither ROS 1 '#ROSBAG V2.0', ROS 2 SQLite .db3 "
                             "nor MCAP by its first bytes)");
}

}  // namespace detail

namespace {

/// Names read from a bag (topics, frames, fields, compression, a library's message quoting
/// them) can hold line breaks: the error that leaves the bag API is kept to one line.
template <class F>
auto oneLineErrors(F&& f) -> decltype(f()) {
    try {
        return f();
    } catch (const std::runtime_error& e) {
        const std::string what = e.what();
        if (what.find_first_of("\n\r") == std::string::npos) throw;
        std::string line;
        for (const char c : what)
            line += (c == '\n' ? "\\n" : c == '\r' ? "\\r" : std::string(1, c));
        throw std::runtime_error(line);
    }
}

}  // namespace

std::vector<BagTopic> listRosbag(const std::string& bag) {
    return oneLineErrors([&] { return detail::listBag(*detail::openBag(bag)); });
}

RosbagImportResult importRosbag(const std::string& bag, const RosbagParams& params,
                                const std::string& out_rawlog, const ProgressFn& progress,
                                const ImportExtras& extras) {
    params.validate();
    return oneLineErrors([&] {
        return detail::importBag(*detail::openBag(bag), params, out_rawlog, progress, extras);
    });
}

}  // namespace superloc::io
