// IMU and odometry CSV files (superloc-import --imu-csv / --odom-csv); see importers.h.
#include <superloc/core/se3.h>
#include <superloc/io/importers.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <stdexcept>

namespace superloc::io {

namespace {

/// Reads the numeric rows of a CSV file (commas and/or blanks between values). A first line
/// that is not all numbers is a header; '#' comments and blank lines are skipped. Each row has
/// one of `counts` values and its first value (time) increases. `what` names the columns.
template <class RowFn>
void readCsv(const std::string& path, std::initializer_list<size_t> counts,
             const std::string& what, RowFn&& row) {
    std::ifstream in(path);
    if (!in) throw std::runtime_error(path + ": cannot open");
    std::string line;
    size_t lineno = 0, rows = 0;
    double last_t = -std::numeric_limits<double>::infinity();
    std::vector<double> v;
    const auto where = [&] { return path + ":" + std::to_string(lineno) + ": "; };
    while (std::getline(in, line)) {
        ++lineno;
        for (char& c : line)
            if (c == ',' || c == ';' || c == '\t' || c == '\r') c = ' ';
        const size_t a = line.find_first_not_of(' ');
        if (a == std::string::npos || line[a] == '#') continue;
        v.clear();
        const char* p = line.c_str() + a;
        bool numeric = true;
        while (*p) {
            char* end = nullptr;
            const double x = std::strtod(p, &end);
            if (end == p || (*end && *end != ' ')) {
                numeric = false;
                break;
            }
            v.push_back(x);
            p = end;
            while (*p == ' ') ++p;
        }
        if (!numeric) {
            if (rows == 0 && lineno == 1) continue;  // header line
            throw std::runtime_error(where() + "not a row of numbers (" + what + ")");
        }
        if (std::find(counts.begin(), counts.end(), v.size()) == counts.end())
            throw std::runtime_error(where() + std::to_string(v.size()) + " values, expected " +
                                     what);
        for (double x : v)
            if (!std::isfinite(x)) throw std::runtime_error(where() + "NaN or infinite value");
        if (!(v[0] > last_t)) throw std::runtime_error(where() + "time does not increase");
        last_t = v[0];
        try {
            row(v);
        } catch (const std::exception& e) {
            throw std::runtime_error(where() + e.what());
        }
        ++rows;
    }
    if (rows == 0) throw std::runtime_error(path + ": no data rows (" + what + ")");
}

}  // namespace

std::vector<ImuSample> loadImuCsv(const std::string& path) {
    std::vector<ImuSample> out;
    readCsv(path, {7}, "7: t ax ay az wx wy wz", [&](const std::vector<double>& v) {
        ImuSample s;
        s.t = v[0];
        s.acc = {v[1], v[2], v[3]};
        s.gyro = {v[4], v[5], v[6]};
        out.push_back(s);
    });
    return out;
}

Trajectory loadOdomCsv(const std::string& path) {
    Trajectory out;
    readCsv(path, {8, 29}, "8: t x y z qx qy qz qw, or 29 with the 21 covariance values",
            [&](const std::vector<double>& v) {
                const double n = std::sqrt(v[4] * v[4] + v[5] * v[5] + v[6] * v[6] + v[7] * v[7]);
                if (std::abs(n - 1.0) > 0.01)
                    throw std::runtime_error("quaternion norm " + std::to_string(n) +
                                             " is not 1 (columns qx qy qz qw)");
                PoseStamped p;
                p.t = v[0];
                p.pose = makePose(v[1], v[2], v[3], v[4] / n, v[5] / n, v[6] / n, v[7] / n);
                if (v.size() == 29) {
                    Mat6d c;
                    size_t k = 8;
                    for (int r = 0; r < 6; ++r)
                        for (int col = r; col < 6; ++col) c(r, col) = c(col, r) = v[k++];
                    p.cov = c;
                }
                out.push_back(p);
            });
    return out;
}

}  // namespace superloc::io
