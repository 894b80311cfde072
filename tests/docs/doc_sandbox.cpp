#include "doc_sandbox.h"

#include <sys/wait.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <stdexcept>

namespace fs = std::filesystem;

namespace superloc::testing::docs {
namespace {

/// What each app's command line promises (doc/design.md#9-command-line): `promise FLAG [FILE...]`
/// lines of the wrapper, FILEs inside the path given after FLAG.
const std::map<std::string, std::string>& promises() {
    static const std::map<std::string, std::string> p = {
        {"superloc-localize", "promise --out trajectory.tum frames.csv summary.json\n"},
        {"superloc-sim", "promise --out sequence.rawlog gt_tum.txt gt_map.ply prior_map.pcd\n"},
        {"superloc-import", "promise --out\npromise --gt-tum\n"},
        {"superloc-map", "promise --out\n"},
        {"superloc-eval", "promise --json\n"},
        {"superloc-bench", "promise --out results.md results.json\n"},
    };
    return p;
}

std::string quoted(const std::string& s) {
    std::string q = "'";
    for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}

void writeExecutable(const fs::path& path, const std::string& text) {
    std::ofstream(path) << text;
    fs::permissions(path, fs::perms::owner_all | fs::perms::group_read | fs::perms::group_exec |
                              fs::perms::others_read | fs::perms::others_exec);
}

/// `dst` holds a link to every entry of `src` except those named in `except`.
void linkEntries(const fs::path& src, const fs::path& dst, const std::set<std::string>& except) {
    for (const auto& e : fs::directory_iterator(src))
        if (!except.count(e.path().filename().string()))
            fs::create_symlink(e.path(), dst / e.path().filename());
}

}  // namespace

std::string appWrapper(const std::string& name, const std::string& real_exe) {
    const auto it = promises().find(name);
    std::string s = "#!/usr/bin/env bash\n# The docs test's stand-in for " + name +
                    " (tests/docs/doc_sandbox.h): the real app, then the outputs it promises.\n";
    if (it == promises().end()) return s + "exec " + quoted(real_exe) + " \"$@\"\n";
    s += quoted(real_exe) + " \"$@\" || exit $?\n";
    s += R"sh(args=("$@")
for a in "${args[@]}"; do
  case "$a" in -h|--help|--dump-config|--list) exit 0 ;; esac
done
missing=0
promise() {  # promise FLAG [FILE...]: the path after FLAG (if given), or FILE... inside it
  local flag=$1 path="" i f p
  shift
  for ((i = 0; i < ${#args[@]}; i++)); do
    case "${args[i]}" in
      "$flag") path=${args[i + 1]:-} ;;
      "$flag"=*) path=${args[i]#*=} ;;
    esac
  done
  [ -n "$path" ] || return 0
  [ $# -gt 0 ] || set -- ""
  for f; do
    p=$path${f:+/$f}
    if [ ! -s "$p" ]; then
      echo "docs-test: )sh" + name + R"sh( exited 0 but did not write $p ($flag)" >&2
      missing=1
    fi
  done
}
)sh";
    return s + it->second + "exit $((missing ? 3 : 0))\n";
}

DocSandbox::DocSandbox(const std::string& dir, const std::string& source_dir, const std::string& build_dir,
                       const std::string& shared_data)
    : dir_(fs::absolute(dir).string()), root_(dir_ + "/root") {
    fs::remove_all(dir_);
    fs::create_directories(root_ + "/build/bin");
    fs::create_directories(dir_ + "/tmp");
    fs::create_directories(dir_ + "/shared");
    fs::create_symlink(fs::absolute(shared_data), dir_ + "/shared/data");
    linkEntries(source_dir, root_, {"build"});
    fs::create_directories(fs::path(build_dir) / "test-output");  // linked, for the tests' outputs
    linkEntries(build_dir, root_ + "/build", {"Testing", "bin"});
    for (const auto& e : fs::directory_iterator(fs::path(build_dir) / "bin")) {
        const auto name = e.path().filename().string();
        if (e.is_regular_file() && promises().count(name))
            writeExecutable(fs::path(root_) / "build/bin" / name, appWrapper(name, fs::absolute(e.path())));
        else
            fs::create_symlink(fs::absolute(e.path()), fs::path(root_) / "build/bin" / name);
    }
}

std::string DocSandbox::withScratchTmp(const std::string& text) const {
    static const std::string kTmp = "/tmp/", kWordStart = " \t\n'\"=(:;|&<>";
    std::string out;
    for (size_t i = 0; i < text.size();) {
        if (text.compare(i, kTmp.size(), kTmp) == 0 && (i == 0 || kWordStart.find(text[i - 1]) != std::string::npos)) {
            out += dir_ + "/tmp/";
            i += kTmp.size();
        } else {
            out += text[i++];
        }
    }
    return out;
}

BlockRun DocSandbox::run(const DocBlock& b) const {
    std::string tag = b.file + "-" + std::to_string(b.line);
    for (char& c : tag)
        if (c == '/' || c == '.') c = '_';
    const std::string script = dir_ + "/" + tag + ".sh", log = dir_ + "/" + tag + ".log";
    const std::string where = b.file + ":" + std::to_string(b.line);
    std::string s = "#!/usr/bin/env bash\n# " + where + ", run by the docs test (tests/docs/doc_sandbox.h)\n" +
                    "set -euo pipefail\nexport PATH=" + quoted(root_ + "/build/bin") + ":\"$PATH\" TMPDIR=" +
                    quoted(dir_ + "/tmp") + "\ncd " + quoted(root_) + "\n";
    s += "trap 'rc=$?; echo \"docs-test: " + where + " (its after marker): exit $rc: $BASH_COMMAND\" >&2' ERR\n";
    for (const auto& a : b.after) s += withScratchTmp(a) + "\n";
    // The block's first line is the page's line b.line + 1 and the script's line `first`.
    const int first = static_cast<int>(std::count(s.begin(), s.end(), '\n')) + 2;
    s += "trap 'rc=$?; echo \"docs-test: " + b.file + ":$((LINENO + " + std::to_string(b.line + 1 - first) +
         ")): exit $rc: $BASH_COMMAND\" >&2' ERR\n";
    s += withScratchTmp(b.text);
    writeExecutable(script, s);

    BlockRun r;
    const auto t0 = std::chrono::steady_clock::now();
    const std::string cmd = "timeout --kill-after=10 " + std::to_string(b.budget_s) + " bash " + quoted(script) +
                            " < /dev/null > " + quoted(log) + " 2>&1";
    const int status = std::system(cmd.c_str());
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    r.over_budget = r.exit_code == 124 || r.exit_code == 137;
    r.log = readText(log);
    if (r.over_budget)
        r.log += "docs-test: " + where + ": over its budget of " + std::to_string(b.budget_s) + " s\n";
    return r;
}

}  // namespace superloc::testing::docs
