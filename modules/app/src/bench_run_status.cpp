#include <superloc/app/bench_run_status.h>
#include <superloc/app/report_plots.h>
#include <superloc/core/config.h>
#include <superloc/io/json_file.h>

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include <cerrno>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace superloc::app {
namespace fs = std::filesystem;
namespace {

const char* kStatus = "status.json";
const char* kComplete = "complete";

std::vector<std::string> dataFiles(const SequenceFiles& f) {
    return {f.rawlog, f.gt_tum, f.gt_map, f.prior_map};
}

}  // namespace

void saveRunStatus(const std::string& dir, const RunStatus& s) {
    const fs::path path = fs::path(dir) / kStatus, tmp = fs::path(dir) / ".status.json.tmp";
    io::saveJson(tmp.string(), {{"id", s.id},
                                {"config", s.config},
                                {"status", s.status},
                                {"exit_code", s.exit_code},
                                {"wall_s", s.wall_s},
                                {"peak_rss_mb", s.peak_rss_mb},
                                {"version", s.version},
                                {"host", s.host},
                                {"finished", s.finished}});
    fs::rename(tmp, path);  // whole or absent, also for a reader on another machine
}

std::optional<RunStatus> loadRunStatus(const std::string& dir) {
    const fs::path path = fs::path(dir) / kStatus;
    if (!fs::exists(path)) return std::nullopt;
    const io::Json j = io::loadJson(path.string());
    try {
        RunStatus s;
        s.id = j.at("id").get<std::string>();
        s.config = j.at("config").get<std::string>();
        s.status = j.at("status").get<std::string>();
        s.exit_code = j.at("exit_code").get<int>();
        s.wall_s = j.at("wall_s").is_null() ? 0.0 : j.at("wall_s").get<double>();
        s.peak_rss_mb = j.at("peak_rss_mb").is_null() ? 0.0 : j.at("peak_rss_mb").get<double>();
        s.version = j.value("version", "");
        s.host = j.value("host", "");
        s.finished = j.value("finished", "");
        return s;
    } catch (const nlohmann::json::exception& e) {
        throw std::runtime_error(path.string() + ": not a run status (" + e.what() + ")");
    }
}

void markDataComplete(const SequenceFiles& f) {
    // File names, not paths: the marker stays true when the output folder is moved or copied.
    std::string text;
    for (const auto& p : dataFiles(f))
        text += std::to_string(fs::file_size(p)) + " " + fs::path(p).filename().string() + "\n";
    const fs::path tmp = fs::path(f.dir) / ".complete.tmp";
    writeTextFile(tmp.string(), text);
    fs::rename(tmp, fs::path(f.dir) / kComplete);
}

std::string dataIncomplete(const SequenceFiles& f, bool gt_only) {
    const fs::path marker = fs::path(f.dir) / kComplete;
    std::ifstream in(marker);
    if (!in) return "no " + marker.string();
    for (const auto& p : dataFiles(f)) {
        std::string line, name;
        unsigned long long size = 0;
        std::getline(in, line);
        std::istringstream ss(line);
        if (!(ss >> size) || !std::getline(ss >> std::ws, name) || name != fs::path(p).filename())
            return marker.string() + " does not list " + fs::path(p).filename().string();
        if (gt_only && p != f.gt_tum && p != f.gt_map) continue;
        std::error_code ec;
        const auto actual = fs::file_size(p, ec);
        if (ec) return p + " is missing";
        if (actual != size)
            return p + " has " + std::to_string(actual) + " bytes, not the " + std::to_string(size) +
                   " it had when written";
    }
    return "";
}

void unmarkDataComplete(const SequenceFiles& f) {
    std::error_code ec;
    fs::remove(fs::path(f.dir) / kComplete, ec);
}

DataLock::DataLock(const std::string& dir) {
    const std::string path = (fs::path(dir) / ".lock").string();
    fd_ = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd_ < 0) throw std::runtime_error(path + ": cannot open (" + std::strerror(errno) + ")");
    if (::flock(fd_, LOCK_EX | LOCK_NB) == 0) return;
    waited_ = true;
    int rc;
    while ((rc = ::flock(fd_, LOCK_EX)) != 0 && errno == EINTR) {
    }
    if (rc != 0) {
        const std::string why = std::strerror(errno);
        ::close(fd_);
        throw std::runtime_error(path + ": cannot lock (" + why + ")");
    }
}

DataLock::~DataLock() {
    if (fd_ >= 0) ::close(fd_);  // releases the lock
}

std::string hostName() {
    char name[256] = {};
    if (::gethostname(name, sizeof name - 1) != 0) return "unknown";
    return name;
}

std::string utcNow() {
    char buf[32];
    const std::time_t now = std::time(nullptr);
    std::tm tm{};
    ::gmtime_r(&now, &tm);
    std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
    return buf;
}

}  // namespace superloc::app
