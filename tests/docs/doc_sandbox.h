// Where the docs test runs a page's ```bash blocks: a copy of the repository root as a reader has
// it after `bash scripts/build.sh`, made of links, so that the commands run as written.
//
//   DIR/root/          every entry of the source tree, linked; the working directory of a block
//   DIR/root/build/    every entry of the build tree, linked, except `Testing` (a nested `ctest
//                      --test-dir build` keeps its logs here, not in the suite's) and `bin`:
//   DIR/root/build/bin/  the build's executables, the apps wrapped (appWrapper) so that a run
//                      that exits 0 without writing the files its command line promises fails
//   DIR/shared/data    the shared data, so that ../shared/data from the root finds it
//   DIR/tmp/           stands for /tmp: "/tmp/..." in a block is rewritten to it, so that runs of
//                      the suite in several build trees at once do not share files
// A block runs as `bash` with `set -euo pipefail`, build/bin first on PATH, in a process group
// that `timeout` ends after the block's budget. Its output goes to a log; an ERR trap names the
// page's line of the command that failed.
#pragma once

#include "doc_blocks.h"

#include <string>

namespace superloc::testing::docs {

/// A bash script standing in for the app `name`: runs `real_exe` with the same arguments and,
/// when it exits 0, checks that every output its command line names (`--out`, `--gt-tum`,
/// `--json`; for superloc-localize, -sim and -bench the files inside --out) exists and is not
/// empty: "docs-test: NAME exited 0 but did not write PATH (--out)", exit 3. --help, -h,
/// --dump-config and --list promise nothing. An app without promises is run as it is.
std::string appWrapper(const std::string& name, const std::string& real_exe);

struct BlockRun {
    int exit_code = 0;        ///< the script's exit code (124: over its budget)
    bool over_budget = false;
    double seconds = 0;
    std::string log;          ///< stdout and stderr of the block, in order
};

class DocSandbox {
   public:
    /// Makes `dir` (emptied first) as above from the source tree `source_dir`, the build tree
    /// `build_dir` and the shared data `shared_data`.
    DocSandbox(const std::string& dir, const std::string& source_dir, const std::string& build_dir,
               const std::string& shared_data);

    /// Runs `block` (its `after` commands first); never throws for a failing block.
    BlockRun run(const DocBlock& block) const;

    /// `text` with every "/tmp/" that starts a word moved under DIR/tmp/.
    std::string withScratchTmp(const std::string& text) const;

    const std::string& root() const { return root_; }

   private:
    std::string dir_, root_;
};

}  // namespace superloc::testing::docs
