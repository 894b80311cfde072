// A simulated sequence shared by the e2e test processes (CTest runs each case in its own
// process, two at a time): the first one to ask runs superloc-sim under a file lock, the others
// wait and reuse it. Re-simulated when superloc-sim is newer than the sequence.
#pragma once

#include <gtest/gtest.h>
#include <superloc_testing/testing.h>
#include <sys/file.h>
#include <unistd.h>

#include <cstdlib>
#include <fcntl.h>
#include <filesystem>
#include <fstream>
#include <string>

namespace superloc::testing {

/// `superloc-sim ini/sim/<world>.ini <args>` into test-output/<name>/seq (sequence.rawlog,
/// gt_tum.txt, prior_map.pcd, ...). Empty when superloc-sim is not built.
inline std::string simulatedSequence(const std::string& name, const std::string& world, const std::string& args) {
    namespace fs = std::filesystem;
    const std::string sim = appPath("superloc-sim");
    if (!fs::exists(sim)) return "";
    const fs::path dir = fs::path(SUPERLOC_BINARY_DIR) / "test-output" / name;
    fs::create_directories(dir);
    const int lock = ::open((dir / "lock").c_str(), O_CREAT | O_RDWR, 0644);
    EXPECT_GE(lock, 0);
    ::flock(lock, LOCK_EX);
    const fs::path done = dir / "seq" / "done";
    if (!fs::exists(done) || fs::last_write_time(done) < fs::last_write_time(sim)) {
        fs::remove_all(dir / "seq");
        const std::string cmd = sim + " " + sourcePath("ini/sim/" + world + ".ini") + " --out " +
                                (dir / "seq").string() + " " + args + " > " + (dir / "sim.log").string() + " 2>&1";
        EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd;
        std::ofstream(done) << "ok\n";
    }
    ::flock(lock, LOCK_UN);
    ::close(lock);
    return (dir / "seq").string();
}

}  // namespace superloc::testing
