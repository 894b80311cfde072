// PCD read/write through PCL (MRPT 2.5.8's loadPCDFile returns no points: NOTES-platform).
// Fields are mapped by name from a PCLPointCloud2, so any PCD with x y z [intensity]
// [normal_x normal_y normal_z] [rgb|rgba] and any numeric type loads.
#include <pcl/PCLPointCloud2.h>
#include <pcl/console/print.h>
#include <pcl/io/pcd_io.h>

#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "cloud_formats.h"

namespace superloc::io::detail {

namespace {

void quietPcl() { pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS); }

const pcl::PCLPointField* findField(const pcl::PCLPointCloud2& c, const char* name) {
    for (const auto& f : c.fields)
        if (f.name == name) return &f;
    return nullptr;
}

/// Reads field `f` of the point starting at `p` as a float, whatever its stored type.
float readAs(const uint8_t* p, const pcl::PCLPointField& f) {
    using T = pcl::PCLPointField::PointFieldTypes;
    p += f.offset;
    switch (f.datatype) {
        case T::INT8: {
            int8_t v;
            std::memcpy(&v, p, 1);
            return v;
        }
        case T::UINT8:
            return *p;
        case T::INT16: {
            int16_t v;
            std::memcpy(&v, p, 2);
            return v;
        }
        case T::UINT16: {
            uint16_t v;
            std::memcpy(&v, p, 2);
            return v;
        }
        case T::INT32: {
            int32_t v;
            std::memcpy(&v, p, 4);
            return static_cast<float>(v);
        }
        case T::UINT32: {
            uint32_t v;
            std::memcpy(&v, p, 4);
            return static_cast<float>(v);
        }
        case T::FLOAT32: {
            float v;
            std::memcpy(&v, p, 4);
            return v;
        }
        case T::FLOAT64: {
            double v;
            std::memcpy(&v, p, 8);
            return static_cast<float>(v);
        }
        default:
            return 0;
    }
}

/// The data lines of an ASCII PCD: PCL reads a value that is not a number as 0 and pads a short
/// line with zeros, so a bad line would be a point at the origin. Each non-blank line must hold
/// `values` numbers, and there must be `points` lines. Errors name the file and line.
void checkAsciiData(const std::string& path, long long offset, size_t lineno, long long values, long long points) {
    std::ifstream in(path, std::ios::binary);
    in.seekg(offset);
    long long n = 0;
    for (std::string line; std::getline(in, line);) {
        ++lineno;
        std::istringstream ss(line);
        long long k = 0;
        for (std::string tok; ss >> tok; ++k) {
            char* end = nullptr;
            std::strtod(tok.c_str(), &end);
            if (end != tok.c_str() + tok.size())
                throw std::runtime_error(path + ":" + std::to_string(lineno) + ": '" + tok.substr(0, 40) +
                                         "' is not a number");
        }
        if (k == 0) continue;  // a blank line
        if (k != values)
            throw std::runtime_error(path + ":" + std::to_string(lineno) + ": " + std::to_string(k) +
                                     " values, the header's FIELDS/COUNT say " + std::to_string(values));
        if (++n > points)
            throw std::runtime_error(path + ":" + std::to_string(lineno) + ": more data lines than the header's " +
                                     std::to_string(points) + " points (POINTS / WIDTH x HEIGHT)");
    }
    if (n < points)
        throw std::runtime_error(path + ": truncated PCD file (" + std::to_string(n) + " data lines for " +
                                 std::to_string(points) + " points)");
}

/// PCL 1.13 accepts some broken headers as an empty cloud (no DATA line) and crashes on
/// others (FIELDS/SIZE/TYPE/COUNT of different lengths): validate the header strictly first.
void checkHeader(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw std::runtime_error(path + ": cannot open");
    const auto bad = [&](const std::string& why) {
        return std::runtime_error(path + ": corrupt PCD header: " + why);
    };
    const auto toInt = [&](const std::string& t, const std::string& key) {
        char* end = nullptr;
        const long long v = std::strtoll(t.c_str(), &end, 10);
        if (t.empty() || end != t.c_str() + t.size() || v < 0 || v > (1LL << 32))
            throw bad(key + " value '" + t + "' is not a count");
        return v;
    };
    std::map<std::string, std::vector<std::string>> h;
    std::string line;
    size_t lineno = 0;  // lines read so far
    for (int n = 0; n < 100 && std::getline(in, line); ++n) {
        ++lineno;
        // PCL trims each line and stops reading the header at one left empty ("\r", blanks):
        // before DATA that leaves it without fields, and its reader dereferences null (found by
        // tests/fuzz/fuzz_pcd.cpp). Only truly empty lines are skipped by both.
        if (!line.empty() && line.find_first_not_of(" \t\r\v\f") == std::string::npos)
            throw bad("blank line with spaces or CR inside the header");
        if (!line.empty() && line.back() == '\r') line.pop_back();
        if (line.empty() || line[0] == '#') continue;
        std::istringstream ss(line);
        std::string key, tok;
        ss >> key;
        static const std::set<std::string> known = {"VERSION", "FIELDS", "SIZE",   "TYPE",
                                                    "COUNT",   "WIDTH",  "HEIGHT", "VIEWPOINT",
                                                    "POINTS",  "DATA"};
        if (!known.count(key)) throw bad("unknown line '" + line.substr(0, 40) + "'");
        if (h.count(key)) throw bad("repeated " + key);
        auto& v = h[key];
        while (ss >> tok) v.push_back(tok);
        if (key == "DATA") break;
    }
    for (const char* k : {"FIELDS", "SIZE", "TYPE", "WIDTH", "HEIGHT", "DATA"})
        if (!h.count(k) || h[k].empty()) throw bad(std::string("no ") + k + " line");
    const size_t nf = h["FIELDS"].size();
    if (h["SIZE"].size() != nf || h["TYPE"].size() != nf ||
        (h.count("COUNT") && h["COUNT"].size() != nf))
        throw bad("FIELDS, SIZE, TYPE and COUNT have different lengths");
    long long step = 0, values = 0;  // bytes and values per point
    for (size_t i = 0; i < nf; ++i) {
        const long long sz = toInt(h["SIZE"][i], "SIZE");
        const long long cnt = h.count("COUNT") ? toInt(h["COUNT"][i], "COUNT") : 1;
        const std::string& ty = h["TYPE"][i];
        if (!(sz == 1 || sz == 2 || sz == 4 || sz == 8) || cnt < 1 || cnt > 1 << 16)
            throw bad("bad SIZE/COUNT of field " + h["FIELDS"][i]);
        if (ty != "F" && ty != "I" && ty != "U") throw bad("bad TYPE '" + ty + "'");
        if (ty == "F" && sz != 4 && sz != 8) throw bad("float field of size " + std::to_string(sz));
        step += sz * cnt;
        values += cnt;
    }
    const long long w = toInt(h["WIDTH"][0], "WIDTH"), ht = toInt(h["HEIGHT"][0], "HEIGHT");
    if (h.count("POINTS") && toInt(h["POINTS"].at(0), "POINTS") != w * ht)
        throw bad("POINTS differs from WIDTH x HEIGHT");
    const std::string data = h["DATA"][0];
    if (data != "ascii" && data != "binary" && data != "binary_compressed")
        throw bad("unknown DATA '" + data + "'");
    const auto header_end = static_cast<long long>(in.tellg());
    // PCL's header parser does not stop at DATA: it goes on reading lines, skipping empty and '#'
    // ones, and takes a line that starts with a header keyword ("COLUMNS", "SIZE", ...) as part of
    // the header, which changes the fields after they were laid out and crashes its reader
    // (found by tests/fuzz/fuzz_pcd.cpp). Refuse data that PCL would read as header.
    for (std::string next; std::getline(in, next);) {
        const size_t b = next.find_first_not_of("\t\r ");  // PCL trims each line
        if (b == std::string::npos || next[b] == '#') continue;
        static const char* keywords[] = {"VERSION", "FIELDS", "COLUMNS", "SIZE", "TYPE",
                                         "COUNT",   "WIDTH",  "HEIGHT",  "VIEWPOINT",
                                         "POINTS",  "DATA"};
        for (const char* k : keywords)
            if (next.compare(b, std::strlen(k), k) == 0)
                throw bad(std::string("data after DATA begins like a header line (") + k + ")");
        break;
    }
    in.clear();
    // PCL allocates WIDTH x HEIGHT points before reading: check the file can hold them (binary:
    // exactly; ASCII: at least "v " per value) so a corrupt count cannot claim gigabytes.
    const auto size = static_cast<long long>(std::filesystem::file_size(path));
    const long long need = data == "binary"  ? w * ht * step
                           : data == "ascii" ? w * ht * static_cast<long long>(nf) * 2 - 1
                                             : 0;
    if (header_end < 0 || size - header_end < need)
        throw std::runtime_error(path + ": truncated PCD file (" +
                                 std::to_string(size - header_end) + " data bytes for " +
                                 std::to_string(w * ht) + " points)");
    // More data than POINTS says: PCL reads POINTS points and drops the rest without a word.
    // (PCL's own binary writer pads the file with zero bytes: those are not data.)
    if (data == "binary" && step > 0 && size - header_end - need >= step) {
        in.clear();
        in.seekg(header_end + need);
        char c = 0;
        while (in.get(c) && c == 0) {
        }
        if (in)
            throw bad("the data holds " + std::to_string((size - header_end) / step) +
                      " points, POINTS / WIDTH x HEIGHT says " + std::to_string(w * ht));
    }
    if (data == "ascii") checkAsciiData(path, header_end, lineno, values, w * ht);
}

}  // namespace

PointCloud readPcd(const std::string& path) {
    quietPcl();
    checkHeader(path);
    pcl::PCLPointCloud2 pc;
    int rc = -1;
    try {
        rc = pcl::io::loadPCDFile(path, pc);
    } catch (const std::exception& e) {
        throw std::runtime_error(path + ": corrupt PCD file (" + std::string(e.what()) + ")");
    }
    if (rc < 0)
        throw std::runtime_error(path + ": corrupt or truncated PCD file (PCL could not read it)");
    const auto *fx = findField(pc, "x"), *fy = findField(pc, "y"), *fz = findField(pc, "z");
    if (!fx || !fy || !fz) throw std::runtime_error(path + ": PCD file has no x y z fields");
    const size_t n = static_cast<size_t>(pc.width) * pc.height;
    if (pc.data.size() < n * pc.point_step)
        throw std::runtime_error(path + ": truncated PCD file (fewer data bytes than points)");
    const auto* fi = findField(pc, "intensity");
    const auto *nx = findField(pc, "normal_x"), *ny = findField(pc, "normal_y"),
               *nz = findField(pc, "normal_z");
    const auto* frgb = findField(pc, "rgb");
    if (!frgb) frgb = findField(pc, "rgba");
    PointCloud c;
    c.points.resize(n);
    if (fi) c.intensity.resize(n);
    const bool has_n = nx && ny && nz;
    if (has_n) c.normals.resize(n);
    if (frgb) c.rgb.resize(n);
    for (size_t i = 0; i < n; ++i) {
        const uint8_t* p = pc.data.data() + i * pc.point_step;
        c.points[i] = Vec3f(readAs(p, *fx), readAs(p, *fy), readAs(p, *fz));
        if (fi) c.intensity[i] = readAs(p, *fi);
        if (has_n) c.normals[i] = Vec3f(readAs(p, *nx), readAs(p, *ny), readAs(p, *nz));
        if (frgb) {
            uint32_t v;
            std::memcpy(&v, p + frgb->offset, 4);
            c.rgb[i] = {uint8_t((v >> 16) & 0xff), uint8_t((v >> 8) & 0xff), uint8_t(v & 0xff)};
        }
    }
    return c;
}

void writePcd(const std::string& path, const PointCloud& c, bool binary) {
    quietPcl();
    pcl::PCLPointCloud2 pc;
    std::vector<std::string> names = {"x", "y", "z"};
    if (!c.intensity.empty()) names.push_back("intensity");
    if (!c.normals.empty()) names.insert(names.end(), {"normal_x", "normal_y", "normal_z"});
    for (size_t k = 0; k < names.size(); ++k) {
        pcl::PCLPointField f;
        f.name = names[k];
        f.offset = static_cast<uint32_t>(4 * k);
        f.datatype = pcl::PCLPointField::FLOAT32;
        f.count = 1;
        pc.fields.push_back(f);
    }
    if (!c.rgb.empty()) {
        pcl::PCLPointField f;
        f.name = "rgb";
        f.offset = static_cast<uint32_t>(4 * names.size());
        f.datatype = pcl::PCLPointField::UINT32;  // packed 0x00RRGGBB
        f.count = 1;
        pc.fields.push_back(f);
    }
    const size_t nf = pc.fields.size();
    pc.point_step = static_cast<uint32_t>(4 * nf);
    pc.width = static_cast<uint32_t>(c.size());
    pc.height = 1;
    pc.row_step = pc.point_step * pc.width;
    pc.is_dense = true;
    pc.data.resize(static_cast<size_t>(pc.row_step));
    for (size_t i = 0; i < c.size(); ++i) {
        float v[7];
        size_t k = 0;
        for (int d = 0; d < 3; ++d) v[k++] = c.points[i][d];
        if (!c.intensity.empty()) v[k++] = c.intensity[i];
        if (!c.normals.empty())
            for (int d = 0; d < 3; ++d) v[k++] = c.normals[i][d];
        uint8_t* p = pc.data.data() + i * pc.point_step;
        std::memcpy(p, v, 4 * k);
        if (!c.rgb.empty()) {
            const uint32_t rgb =
                (uint32_t(c.rgb[i][0]) << 16) | (uint32_t(c.rgb[i][1]) << 8) | c.rgb[i][2];
            std::memcpy(p + 4 * k, &rgb, 4);
        }
    }
    pcl::PCDWriter w;
    int rc = -1;
    try {
        rc = binary ? w.writeBinary(path, pc)
                    : w.writeASCII(path, pc, Eigen::Vector4f::Zero(),
                                   Eigen::Quaternionf::Identity(), 9);
    } catch (const std::exception& e) {
        throw std::runtime_error(path + ": cannot write PCD (" + std::string(e.what()) + ")");
    }
    if (rc < 0) throw std::runtime_error(path + ": cannot write PCD");
}

}  // namespace superloc::io::detail
