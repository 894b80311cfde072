// sensor_msgs/PointCloud2 payload -> Scan (points, intensity, per-point time). See pointcloud2.h.
#include "pointcloud2.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>

namespace superloc::io::detail {

namespace {

size_t typeSize(uint8_t t) {
    switch (t) {
        case 1: case 2: return 1;
        case 3: case 4: return 2;
        case 5: case 6: case 7: return 4;
        case 8: return 8;
        default: return 0;
    }
}

/// Reads one scalar of PointField datatype `t` at `p` (byte order swapped when `swap`).
double readScalar(const uint8_t* p, uint8_t t, bool swap) {
    uint8_t b[8];
    const size_t n = typeSize(t);
    std::memcpy(b, p, n);
    if (swap) std::reverse(b, b + n);
    switch (t) {
        case 1: { int8_t v; std::memcpy(&v, b, 1); return v; }
        case 2: { uint8_t v; std::memcpy(&v, b, 1); return v; }
        case 3: { int16_t v; std::memcpy(&v, b, 2); return v; }
        case 4: { uint16_t v; std::memcpy(&v, b, 2); return v; }
        case 5: { int32_t v; std::memcpy(&v, b, 4); return v; }
        case 6: { uint32_t v; std::memcpy(&v, b, 4); return v; }
        case 7: { float v; std::memcpy(&v, b, 4); return v; }
        default: { double v; std::memcpy(&v, b, 8); return v; }
    }
}

const PointField2* findField(const PointCloud2View& pc, const std::string& name) {
    for (const auto& f : pc.fields)
        if (f.name == name) return &f;
    return nullptr;
}

double unitScale(const std::string& unit, uint8_t datatype) {
    if (unit == "s") return 1.0;
    if (unit == "ms") return 1e-3;
    if (unit == "us") return 1e-6;
    if (unit == "ns") return 1e-9;
    if (unit == "auto") return (datatype == 7 || datatype == 8) ? 1.0 : 1e-9;
    throw std::runtime_error("point_time_unit '" + unit + "' is not auto, s, ms, us or ns");
}

}  // namespace

std::string printable(const std::string& s, size_t max_len) {
    std::string out;
    for (const char ch : s) {
        const auto c = static_cast<unsigned char>(ch);
        if (out.size() >= max_len) return out + "...";
        if (c >= 0x20 && c < 0x7f) {
            out += ch;
        } else {
            const char* d = "0123456789abcdef";
            out += {'\\', 'x', d[c >> 4], d[c & 15]};
        }
    }
    return out;
}

PointCloud2Stats decodePointCloud2(const PointCloud2View& pc, const PointTimeOptions& opt,
                                   Scan& scan) {
    PointCloud2Stats st;
    const PointField2* fx = findField(pc, "x");
    const PointField2* fy = findField(pc, "y");
    const PointField2* fz = findField(pc, "z");
    if (!fx || !fy || !fz) throw std::runtime_error("PointCloud2 without x, y and z fields");
    for (const auto& f : pc.fields) {
        const size_t sz = typeSize(f.datatype);
        if (sz == 0)
            throw std::runtime_error("PointCloud2 field '" + printable(f.name) +
                                     "' has unknown datatype " +
                                     std::to_string(int(f.datatype)));
        if (size_t(f.offset) + sz > pc.point_step)
            throw std::runtime_error("PointCloud2 field '" + printable(f.name) +
                                     "' does not fit in point_step " +
                                     std::to_string(pc.point_step));
    }
    const size_t n = size_t(pc.width) * pc.height;
    if (n > 0 && (size_t(pc.row_step) < size_t(pc.width) * pc.point_step ||
                  pc.data_size < size_t(pc.row_step) * (pc.height - 1) +
                                     size_t(pc.width) * pc.point_step))
        throw std::runtime_error("PointCloud2 data holds " + std::to_string(pc.data_size) +
                                 " bytes, less than its " + std::to_string(pc.height) + " x " +
                                 std::to_string(pc.width) + " points need");

    const PointField2* fi = findField(pc, "intensity");
    const PointField2* ft = nullptr;
    if (opt.field == "auto") {
        for (const char* name : {"t", "time", "timestamp", "offset_time"})
            if ((ft = findField(pc, name))) break;
    } else if (opt.field != "none") {
        ft = findField(pc, opt.field);
        if (!ft)
            throw std::runtime_error("PointCloud2 has no per-point time field '" +
                                     printable(opt.field) +
                                     "' ([rosbag] point_time_field)");
    }
    if (opt.reference != "auto" && opt.reference != "relative" && opt.reference != "absolute")
        throw std::runtime_error("point_time_reference '" + opt.reference +
                                 "' is not auto, relative or absolute");
    const double tscale = ft ? unitScale(opt.unit, ft->datatype) : 1.0;

    if (n == 0) {  // e.g. width 0 with a huge height: nothing to read (found by fuzz_cdr)
        scan = Scan();
        scan.t = pc.stamp;
        return st;
    }
    const bool swap = pc.is_bigendian != (__BYTE_ORDER__ == __ORDER_BIG_ENDIAN__);
    const bool fast_xyz = !swap && fx->datatype == 7 && fy->datatype == 7 && fz->datatype == 7;
    scan = Scan();
    scan.t = pc.stamp;
    scan.points.reserve(n);
    if (fi) scan.intensity.reserve(n);
    std::vector<double> times;
    if (ft) times.reserve(n);
    for (uint32_t r = 0; r < pc.height; ++r) {
        const uint8_t* row = pc.data + size_t(r) * pc.row_step;
        for (uint32_t c = 0; c < pc.width; ++c) {
            const uint8_t* p = row + size_t(c) * pc.point_step;
            float x, y, z;
            if (fast_xyz) {
                std::memcpy(&x, p + fx->offset, 4);
                std::memcpy(&y, p + fy->offset, 4);
                std::memcpy(&z, p + fz->offset, 4);
            } else {
                x = float(readScalar(p + fx->offset, fx->datatype, swap));
                y = float(readScalar(p + fy->offset, fy->datatype, swap));
                z = float(readScalar(p + fz->offset, fz->datatype, swap));
            }
            if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z)) {
                ++st.invalid_points;
                continue;
            }
            scan.points.emplace_back(x, y, z);
            if (fi) scan.intensity.push_back(float(readScalar(p + fi->offset, fi->datatype, swap)));
            if (ft) times.push_back(readScalar(p + ft->offset, ft->datatype, swap) * tscale);
        }
    }
    if (ft && !times.empty()) {
        st.time_field = ft->name;
        bool absolute = opt.reference == "absolute";
        if (opt.reference == "auto") {
            // Absolute stamps lie near header.stamp; relative ones near 0.
            const double v = times[times.size() / 2];
            absolute = std::abs(v - pc.stamp) < std::abs(v);
        }
        st.time_absolute = absolute;
        scan.rel_time.resize(times.size());
        for (size_t i = 0; i < times.size(); ++i)
            scan.rel_time[i] = float(absolute ? times[i] - pc.stamp : times[i]);
    }
    return st;
}

}  // namespace superloc::io::detail
