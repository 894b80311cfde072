// PLY read/write (ASCII, binary little- and big-endian). Written here: a vertex element with
// x y z [intensity] [nx ny nz] [red green blue]. Read: any vertex properties of scalar type
// (x y z required; intensity|scalar_intensity|reflectance, nx ny nz|normal_x.., red green blue
// used), other elements after the vertices are ignored.
#include <superloc/io/point_cloud_io.h>

#include <algorithm>
#include <array>
#include <functional>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "cloud_formats.h"

namespace superloc::io::detail {

namespace {

struct Prop {
    std::string name;
    int size = 0;     // bytes
    char kind = 'f';  // 'f' float, 'i' signed, 'u' unsigned
};

bool scalarType(const std::string& t, Prop& p) {
    static const struct {
        const char* n;
        int s;
        char k;
    } types[] = {{"char", 1, 'i'},  {"int8", 1, 'i'},    {"uchar", 1, 'u'},  {"uint8", 1, 'u'},
                 {"short", 2, 'i'}, {"int16", 2, 'i'},   {"ushort", 2, 'u'}, {"uint16", 2, 'u'},
                 {"int", 4, 'i'},   {"int32", 4, 'i'},   {"uint", 4, 'u'},   {"uint32", 4, 'u'},
                 {"float", 4, 'f'}, {"float32", 4, 'f'}, {"double", 8, 'f'}, {"float64", 8, 'f'}};
    for (const auto& ty : types)
        if (t == ty.n) return p.size = ty.s, p.kind = ty.k, true;
    return false;
}

/// The value of type T stored in the first sizeof(T) bytes of b.
template <class T>
double as(const char* b) {
    T v;
    std::memcpy(&v, b, sizeof v);
    return static_cast<double>(v);
}

double decode(const char* b, const Prop& p, bool swap) {
    char tmp[8];
    std::memcpy(tmp, b, p.size);
    if (swap) std::reverse(tmp, tmp + p.size);
    switch (p.kind) {
        case 'f': return p.size == 4 ? as<float>(tmp) : as<double>(tmp);
        case 'i':
            return p.size == 1 ? as<int8_t>(tmp) : p.size == 2 ? as<int16_t>(tmp) : as<int32_t>(tmp);
        default:
            return p.size == 1 ? as<uint8_t>(tmp) : p.size == 2 ? as<uint16_t>(tmp) : as<uint32_t>(tmp);
    }
}

int indexOf(const std::vector<Prop>& props, std::initializer_list<const char*> names) {
    for (const char* n : names)
        for (size_t i = 0; i < props.size(); ++i)
            if (props[i].name == n) return static_cast<int>(i);
    return -1;
}

}  // namespace

PointCloud readPly(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw std::runtime_error(path + ": cannot open");
    const auto bad = [&](const std::string& why) {
        return std::runtime_error(path + ": bad PLY: " + why);
    };
    std::string line;
    if (!std::getline(in, line) || line.substr(0, 3) != "ply") throw bad("missing 'ply' magic");
    std::string format;
    size_t n_vertex = 0;
    bool in_vertex = false, vertex_seen = false, vertex_first = true;
    std::vector<Prop> props;
    while (true) {
        if (!std::getline(in, line)) throw bad("header not terminated by end_header");
        if (!line.empty() && line.back() == '\r') line.pop_back();
        std::istringstream ss(line);
        std::string kw;
        ss >> kw;
        if (kw == "end_header") break;
        if (kw == "format") {
            ss >> format;
        } else if (kw == "element") {
            std::string name;
            long long count = -1;
            ss >> name >> count;
            if (count < 0) throw bad("element '" + name + "' without a valid count");
            in_vertex = name == "vertex";
            if (in_vertex) {
                vertex_seen = true;
                n_vertex = static_cast<size_t>(count);
            } else if (!vertex_seen && count > 0) {
                vertex_first = false;
            }
        } else if (kw == "property" && in_vertex) {
            std::string type, name;
            ss >> type >> name;
            Prop p;
            p.name = name;
            if (type == "list" || !scalarType(type, p))
                throw bad("unsupported vertex property type '" + type + "'");
            props.push_back(p);
        }
    }
    if (format != "ascii" && format != "binary_little_endian" && format != "binary_big_endian")
        throw bad("unknown format '" + format + "'");
    if (!vertex_seen) throw bad("no vertex element");
    if (!vertex_first) throw bad("elements before 'vertex' are not supported");
    const int ix = indexOf(props, {"x"}), iy = indexOf(props, {"y"}), iz = indexOf(props, {"z"});
    if (ix < 0 || iy < 0 || iz < 0) throw bad("vertex element has no x y z");
    const int ii =
        indexOf(props, {"intensity", "scalar_intensity", "reflectance", "scalar_Intensity"});
    const int inx = indexOf(props, {"nx", "normal_x"}), iny = indexOf(props, {"ny", "normal_y"}),
              inz = indexOf(props, {"nz", "normal_z"});
    const int ir = indexOf(props, {"red", "r"}), ig = indexOf(props, {"green", "g"}),
              ib = indexOf(props, {"blue", "b"});
    const bool has_n = inx >= 0 && iny >= 0 && inz >= 0, has_c = ir >= 0 && ig >= 0 && ib >= 0;

    // Check the file can hold the vertices before allocating them (a corrupt count must not
    // claim gigabytes): binary exactly, ASCII at least "v " per value.
    {
        size_t stride = 0;
        for (const auto& p : props) stride += p.size;
        const auto here = static_cast<long long>(in.tellg());
        const auto size = static_cast<long long>(std::filesystem::file_size(path));
        const long double need = format == "ascii" ? (long double)n_vertex * props.size() * 2 - 1
                                                   : (long double)n_vertex * stride;
        if (here < 0 || (long double)(size - here) < need)
            throw bad("truncated: " + std::to_string(n_vertex) + " vertices do not fit in the " +
                      std::to_string(size - here) + " data bytes");
    }
    PointCloud c;
    c.points.resize(n_vertex);
    if (ii >= 0) c.intensity.resize(n_vertex);
    if (has_n) c.normals.resize(n_vertex);
    if (has_c) c.rgb.resize(n_vertex);
    std::vector<double> v(props.size());
    const auto store = [&](size_t k) {
        c.points[k] = Vec3f(float(v[ix]), float(v[iy]), float(v[iz]));
        if (ii >= 0) c.intensity[k] = float(v[ii]);
        if (has_n) c.normals[k] = Vec3f(float(v[inx]), float(v[iny]), float(v[inz]));
        if (has_c) c.rgb[k] = {uint8_t(v[ir]), uint8_t(v[ig]), uint8_t(v[ib])};
    };
    if (format == "ascii") {
        for (size_t k = 0; k < n_vertex; ++k) {
            if (!std::getline(in, line))
                throw bad("truncated: " + std::to_string(k) + " of " + std::to_string(n_vertex) +
                          " vertices");
            std::istringstream ss(line);
            for (size_t j = 0; j < props.size(); ++j)
                if (!(ss >> v[j]))
                    throw bad("vertex " + std::to_string(k) + ": expected " +
                              std::to_string(props.size()) +
                              " numbers (truncated or malformed line)");
            store(k);
        }
    } else {
        const bool swap = format == "binary_big_endian";  // this machine is little-endian
        size_t stride = 0;
        for (const auto& p : props) stride += p.size;
        std::vector<char> buf(stride * std::min<size_t>(n_vertex, 65536));
        for (size_t k0 = 0; k0 < n_vertex; k0 += 65536) {
            const size_t m = std::min<size_t>(65536, n_vertex - k0);
            in.read(buf.data(), static_cast<std::streamsize>(m * stride));
            if (in.gcount() != static_cast<std::streamsize>(m * stride))
                throw bad("truncated: file ends inside the vertex data");
            for (size_t k = 0; k < m; ++k) {
                const char* b = buf.data() + k * stride;
                for (size_t j = 0; j < props.size(); ++j) {
                    v[j] = decode(b, props[j], swap);
                    b += props[j].size;
                }
                store(k0 + k);
            }
        }
    }
    return c;
}

namespace {
/// The header of a vertex element of n points with the attributes asked for.
void writePlyHeader(std::ostream& out, bool binary, size_t n, bool has_i, bool has_n, bool has_c) {
    out << "ply\nformat " << (binary ? "binary_little_endian" : "ascii") << " 1.0\n"
        << "comment written by SuperLoc\nelement vertex " << n << "\n"
        << "property float x\nproperty float y\nproperty float z\n";
    if (has_i) out << "property float intensity\n";
    if (has_n) out << "property float nx\nproperty float ny\nproperty float nz\n";
    if (has_c) out << "property uchar red\nproperty uchar green\nproperty uchar blue\n";
    out << "end_header\n";
}
}  // namespace

void writePly(const std::string& path, const PointCloud& c, bool binary) {
    std::ofstream out(path, std::ios::binary);
    if (!out) throw std::runtime_error(path + ": cannot write");
    const bool has_i = !c.intensity.empty(), has_n = !c.normals.empty(), has_c = !c.rgb.empty();
    writePlyHeader(out, binary, c.size(), has_i, has_n, has_c);
    if (binary) {
        std::vector<char> rec;
        for (size_t i = 0; i < c.size(); ++i) {
            rec.clear();
            const auto put = [&](const void* p, size_t s) {
                rec.insert(rec.end(), static_cast<const char*>(p), static_cast<const char*>(p) + s);
            };
            put(c.points[i].data(), 12);
            if (has_i) put(&c.intensity[i], 4);
            if (has_n) put(c.normals[i].data(), 12);
            if (has_c) put(c.rgb[i].data(), 3);
            out.write(rec.data(), static_cast<std::streamsize>(rec.size()));
        }
    } else {
        char buf[256];
        for (size_t i = 0; i < c.size(); ++i) {
            const auto& p = c.points[i];
            int n = std::snprintf(buf, sizeof(buf), "%.9g %.9g %.9g", p.x(), p.y(), p.z());
            if (has_i) n += std::snprintf(buf + n, sizeof(buf) - n, " %.9g", c.intensity[i]);
            if (has_n)
                n += std::snprintf(buf + n, sizeof(buf) - n, " %.9g %.9g %.9g", c.normals[i].x(),
                                   c.normals[i].y(), c.normals[i].z());
            if (has_c)
                n += std::snprintf(buf + n, sizeof(buf) - n, " %d %d %d", c.rgb[i][0], c.rgb[i][1],
                                   c.rgb[i][2]);
            out << buf << '\n';
        }
    }
    out.flush();
    if (!out) throw std::runtime_error(path + ": write error");
}

}  // namespace superloc::io::detail

namespace superloc::io {

void saveColouredPly(const std::string& path, const std::vector<Vec3f>& points,
                     const std::function<std::array<uint8_t, 3>(size_t)>& colour) {
    std::ofstream out(path, std::ios::binary);
    if (!out) throw std::runtime_error(path + ": cannot write");
    detail::writePlyHeader(out, true, points.size(), false, false, true);
    for (size_t i = 0; i < points.size(); ++i) {
        const std::array<uint8_t, 3> rgb = colour(i);
        out.write(reinterpret_cast<const char*>(points[i].data()), 12);
        out.write(reinterpret_cast<const char*>(rgb.data()), 3);
    }
    out.flush();
    if (!out) throw std::runtime_error(path + ": write error");
}

}  // namespace superloc::io
