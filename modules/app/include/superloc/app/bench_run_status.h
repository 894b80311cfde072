// What each run of a benchmark suite leaves in its folder, so that `superloc-bench --collect` can
// tell a finished run from a failed or missing one (doc/evaluation.md#runs-split-for-a-scheduler):
// status.json, the data's completion marker, and the lock one data run of a sequence holds.
#pragma once

#include <superloc/app/suite.h>

#include <optional>
#include <string>

namespace superloc::app {

/// What a run left in its folder when it ended (status.json).
struct RunStatus {
    std::string id;
    std::string config;         ///< configStamp of the configuration it ran with
    std::string status = "ok";  ///< "ok", "exit 3", "timeout after 900 s", ...; a data run: why it failed
    int exit_code = 0;          ///< of the child (the last one of a data run); -1 when none ran
    double wall_s = 0;          ///< [s]
    double peak_rss_mb = 0;     ///< [MiB]
    std::string version;        ///< the superloc-bench build that ran it
    std::string host;           ///< the machine it ran on
    std::string finished;       ///< UTC, ISO 8601
};
/// Writes dir/status.json whole (a temporary file renamed over it).
void saveRunStatus(const std::string& dir, const RunStatus& s);
/// dir/status.json; nullopt when absent. Throws std::runtime_error naming a malformed file.
std::optional<RunStatus> loadRunStatus(const std::string& dir);

/// Marks a sequence's data complete: f.dir/complete lists each file of `f` with its size.
/// Written last, once every file is in place.
void markDataComplete(const SequenceFiles& f);
/// "" when f.dir/complete exists and every file it lists is there with its size (with
/// `gt_only`, the ground truth's files: what --collect reads); otherwise why not.
std::string dataIncomplete(const SequenceFiles& f, bool gt_only = false);
/// Removes f.dir/complete (the data is about to be rewritten or deleted).
void unmarkDataComplete(const SequenceFiles& f);

/// An exclusive lock (flock) on dir/.lock for the object's life: one data run of a sequence at
/// a time, also across machines whose shared folder supports locks (NFS does).
class DataLock {
 public:
    explicit DataLock(const std::string& dir);
    ~DataLock();
    DataLock(const DataLock&) = delete;
    DataLock& operator=(const DataLock&) = delete;
    /// Another process held the lock when this one asked for it.
    bool waited() const { return waited_; }

 private:
    int fd_ = -1;
    bool waited_ = false;
};

/// This machine's name, and the current UTC time as 2026-01-31T12:00:00Z.
std::string hostName();
std::string utcNow();

}  // namespace superloc::app
