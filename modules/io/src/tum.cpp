// TUM trajectory files: "t x y z qx qy qz qw" per line, '#' comments.
#include <superloc/core/se3.h>
#include <superloc/io/tum.h>

#include <cmath>
#include <cstdio>
#include <sstream>
#include <stdexcept>

namespace superloc::io {

namespace {
std::string where(const std::string& path, size_t line) {
    return path + ":" + std::to_string(line) + ": ";
}
}  // namespace

Trajectory loadTum(const std::string& path) {
    std::ifstream in(path);
    if (!in) throw std::runtime_error(path + ": cannot open TUM file");
    Trajectory traj;
    std::string line;
    size_t lineno = 0, last_line = 0;  // last_line: the line of traj.back()
    while (std::getline(in, line)) {
        ++lineno;
        const size_t first = line.find_first_not_of(" \t\r");
        if (first == std::string::npos || line[first] == '#') continue;
        std::istringstream ss(line);
        double v[8];
        for (int i = 0; i < 8; ++i) {
            if (!(ss >> v[i]))
                throw std::runtime_error(where(path, lineno) +
                                         "expected 8 numbers 't x y z qx qy qz qw', got '" +
                                         line.substr(first) + "'");
            if (!std::isfinite(v[i]))
                throw std::runtime_error(where(path, lineno) + "non-finite value");
        }
        std::string extra;
        if (ss >> extra)
            throw std::runtime_error(where(path, lineno) + "unexpected trailing text '" + extra +
                                     "'");
        const double qn = std::sqrt(v[4] * v[4] + v[5] * v[5] + v[6] * v[6] + v[7] * v[7]);
        if (qn < 1e-6 || std::abs(qn - 1.0) > 1e-2)
            throw std::runtime_error(where(path, lineno) + "quaternion is not unit (norm " +
                                     std::to_string(qn) + ")");
        if (!traj.empty() && v[0] < traj.back().t)
            throw std::runtime_error(where(path, lineno) + "timestamp goes backwards (" +
                                     std::to_string(v[0]) + " < " + std::to_string(traj.back().t) +
                                     ")");
        // Two poses at one time: which one a pairing by time takes would depend on the line order.
        if (!traj.empty() && v[0] == traj.back().t)
            throw std::runtime_error(where(path, lineno) + "timestamp " + line.substr(first, line.find_first_of(" \t", first) - first) +
                                     " repeats line " + std::to_string(last_line));
        last_line = lineno;
        PoseStamped p;
        p.t = v[0];
        p.pose = makePose(v[1], v[2], v[3], v[4], v[5], v[6], v[7]);
        traj.push_back(p);
    }
    if (in.bad()) throw std::runtime_error(path + ": read error");
    return traj;
}

std::string formatTumLine(double t, const SE3d& pose) {
    const Eigen::Quaterniond q(pose.linear());
    const Vec3d& x = pose.translation();
    char buf[256];
    std::snprintf(buf, sizeof(buf), "%.9f %.15g %.15g %.15g %.15g %.15g %.15g %.15g", t, x.x(),
                  x.y(), x.z(), q.x(), q.y(), q.z(), q.w());
    return buf;
}

void saveTum(const std::string& path, const Trajectory& traj) {
    std::ofstream out(path);
    if (!out) throw std::runtime_error(path + ": cannot write TUM file");
    out << "# t x y z qx qy qz qw\n";
    for (const auto& p : traj) out << formatTumLine(p.t, p.pose) << '\n';
    out.flush();
    if (!out) throw std::runtime_error(path + ": write error");
}

TumWriter::TumWriter(const std::string& path, const std::string& header_comment)
    : path_(path), out_(path) {
    if (!out_) throw std::runtime_error(path + ": cannot write TUM file");
    if (!header_comment.empty()) {
        std::istringstream ss(header_comment);
        std::string l;
        while (std::getline(ss, l)) out_ << "# " << l << '\n';
    }
    out_ << "# t x y z qx qy qz qw" << std::endl;
}

void TumWriter::write(const PoseStamped& p) { write(p.t, p.pose); }

void TumWriter::write(double t, const SE3d& pose) {
    out_ << formatTumLine(t, pose) << std::endl;
    if (!out_) throw std::runtime_error(path_ + ": write error");
}

}  // namespace superloc::io
