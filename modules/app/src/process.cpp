#include <fcntl.h>
#include <signal.h>
#include <superloc/app/process.h>
#include <sys/time.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

namespace superloc::app {
namespace fs = std::filesystem;
namespace {
// The pids of the running children (0: a free slot), one per concurrent runProcess
// (superloc-bench --jobs). Lock-free atomics, so the signal handler may read them.
std::atomic<pid_t> g_children[kMaxChildren] = {};
static_assert(std::atomic<pid_t>::is_always_lock_free);

void onTermination(int sig) {
    for (auto& c : g_children)
        if (const pid_t pid = c.load(); pid > 0) ::kill(pid, SIGKILL);
    ::_exit(128 + sig);
}

/// Remembers a child for onTermination; the slot, or nullptr when all are taken (more than
/// kMaxChildren at once: that child is not killed on a signal).
std::atomic<pid_t>* registerChild(pid_t pid) {
    for (auto& c : g_children) {
        pid_t free_slot = 0;
        if (c.compare_exchange_strong(free_slot, pid)) return &c;
    }
    return nullptr;
}

/// [MiB] VmHWM (peak resident memory) of a running process's current program, 0 when it cannot
/// be read (e.g. the process has exited).
double peakResidentMiB(pid_t pid) {
    std::ifstream status("/proc/" + std::to_string(pid) + "/status");
    for (std::string line; std::getline(status, line);)
        if (line.rfind("VmHWM:", 0) == 0) return std::atof(line.c_str() + 6) / 1024.0;  // kB
    return 0;
}
}  // namespace

void killChildOnTermination() {
    struct sigaction sa {};
    sa.sa_handler = onTermination;
    sigemptyset(&sa.sa_mask);
    ::sigaction(SIGINT, &sa, nullptr);
    ::sigaction(SIGTERM, &sa, nullptr);
}

ProcessResult runProcess(const std::vector<std::string>& argv, const std::string& log_path,
                         double timeout_s) {
    ProcessResult r;
    if (argv.empty()) return r;
    std::vector<char*> cargs;
    for (const auto& a : argv) cargs.push_back(const_cast<char*>(a.c_str()));
    cargs.push_back(nullptr);
    const int log_fd = ::open(log_path.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
    if (log_fd < 0) return r;
    // Closed by a successful exec: the parent reads end-of-file once the child runs its program
    // (or the child's errno when exec failed).
    int exec_pipe[2];
    if (::pipe2(exec_pipe, O_CLOEXEC) != 0) {
        ::close(log_fd);
        return r;
    }
    const auto t0 = std::chrono::steady_clock::now();
    const pid_t pid = ::fork();
    if (pid < 0) {
        ::close(log_fd), ::close(exec_pipe[0]), ::close(exec_pipe[1]);
        return r;
    }
    if (pid == 0) {  // child: output to the log, then exec
        ::dup2(log_fd, STDOUT_FILENO);
        ::dup2(log_fd, STDERR_FILENO);
        const int devnull = ::open("/dev/null", O_RDONLY);
        if (devnull >= 0) ::dup2(devnull, STDIN_FILENO);
        ::execvp(cargs[0], cargs.data());
        const int err = errno;
        [[maybe_unused]] const ssize_t n = ::write(exec_pipe[1], &err, sizeof err);
        ::_exit(127);
    }
    ::close(log_fd);
    ::close(exec_pipe[1]);
    std::atomic<pid_t>* slot = registerChild(pid);
    int exec_errno = 0;
    ssize_t got;
    while ((got = ::read(exec_pipe[0], &exec_errno, sizeof exec_errno)) < 0 && errno == EINTR) {
    }
    ::close(exec_pipe[0]);
    const bool exec_failed = got == static_cast<ssize_t>(sizeof exec_errno);
    int status = 0;
    for (;;) {
        // The peak memory of the child's program, read while it runs: rusage's ru_maxrss would
        // also count the pages the child had from this process at fork, i.e. the bench's own
        // memory (and with --jobs, whatever the other runs' evaluations hold at that moment).
        if (!exec_failed) r.peak_rss_mb = std::max(r.peak_rss_mb, peakResidentMiB(pid));
        const pid_t w = ::waitpid(pid, &status, WNOHANG);
        if (w == pid) break;
        const double elapsed =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        if (timeout_s > 0 && elapsed > timeout_s && !r.timed_out) {
            ::kill(pid, SIGKILL);  // only our own child, by its pid
            r.timed_out = true;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    if (slot) slot->store(0);
    r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (WIFEXITED(status))
        r.exit_code = WEXITSTATUS(status);
    else if (WIFSIGNALED(status))
        r.exit_code = 128 + WTERMSIG(status);
    r.started = !exec_failed;
    return r;
}

std::string findTool(const std::string& name, const std::string& dir) {
    std::vector<fs::path> candidates = {fs::path(dir) / name, fs::path(dir) / ".." / name / name};
    if (const char* path = std::getenv("PATH")) {
        std::istringstream ss(path);
        for (std::string p; std::getline(ss, p, ':');)
            if (!p.empty()) candidates.push_back(fs::path(p) / name);
    }
    for (const auto& c : candidates)
        if (fs::is_regular_file(c) && ::access(c.c_str(), X_OK) == 0)
            return fs::absolute(c).lexically_normal().string();
    return "";
}

std::string selfExe() {
    std::error_code ec;
    const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    return ec ? std::string() : exe.string();
}

std::string selfDir() {
    const std::string exe = selfExe();
    return exe.empty() ? std::string(".") : fs::path(exe).parent_path().string();
}

}  // namespace superloc::app
