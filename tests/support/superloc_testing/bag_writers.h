// Test support only (not shipped): writers of ROS 2 bags for round-trip tests — CDR encoding of
// the five message types SuperLoc reads, a rosbag2 SQLite `.db3` and an MCAP file (chunks
// uncompressed, zstd or lz4, or no chunks). Written from the same public specifications as the
// readers (modules/io/src/bag/), but independently of them: the tests compare what goes in here
// with what comes out there. Links sqlite3, zstd, lz4 and zlib.
#pragma once

#include <lz4frame.h>
#include <sqlite3.h>
#include <zlib.h>
#include <zstd.h>

#include <array>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace superloc::testing::bag {

struct Time {
    int32_t sec = 0;
    uint32_t nsec = 0;
    int64_t ns() const { return int64_t(sec) * 1000000000 + nsec; }
};

struct Field {
    std::string name;
    uint32_t offset = 0;
    uint8_t datatype = 7;  ///< 7 FLOAT32
    uint32_t count = 1;
};

struct Cloud {
    Time stamp;
    std::string frame;
    uint32_t height = 1, width = 0, point_step = 0, row_step = 0;
    std::vector<Field> fields;
    bool is_bigendian = false, is_dense = true;
    std::vector<uint8_t> data;
};

struct Pose {
    double x = 0, y = 0, z = 0, qx = 0, qy = 0, qz = 0, qw = 1;
};

struct Imu {
    Time stamp;
    std::string frame;
    std::array<double, 3> gyro{}, acc{};
};

struct Odometry {
    Time stamp;
    std::string frame, child;
    Pose pose;
    std::array<double, 36> covariance{};
};

struct PoseStamped {
    Time stamp;
    std::string frame;
    Pose pose;
};

struct Transform {
    Time stamp;
    std::string parent, child;
    Pose T;
};

/// XCDR1 little endian: the 4-byte encapsulation header, then fields aligned to their size
/// counted from the end of the header.
class CdrWriter {
 public:
    std::vector<uint8_t> buf{0x00, 0x01, 0x00, 0x00};
    void align(size_t n) {
        while ((buf.size() - 4) % n) buf.push_back(0);
    }
    template <class T>
    void put(T v) {
        align(sizeof(T));
        uint8_t b[sizeof(T)];
        std::memcpy(b, &v, sizeof(T));
        buf.insert(buf.end(), b, b + sizeof(T));
    }
    void str(const std::string& s) {
        put(uint32_t(s.size() + 1));
        buf.insert(buf.end(), s.begin(), s.end());
        buf.push_back(0);
    }
    void header(const Time& t, const std::string& frame) {
        put(t.sec);
        put(t.nsec);
        str(frame);
    }
    void pose(const Pose& p) {
        for (double v : {p.x, p.y, p.z, p.qx, p.qy, p.qz, p.qw}) put(v);
    }
};

inline std::vector<uint8_t> cdr(const Cloud& c) {
    CdrWriter w;
    w.header(c.stamp, c.frame);
    w.put(c.height);
    w.put(c.width);
    w.put(uint32_t(c.fields.size()));
    for (const auto& f : c.fields) {
        w.str(f.name);
        w.put(f.offset);
        w.put(f.datatype);
        w.put(f.count);
    }
    w.put(uint8_t(c.is_bigendian));
    w.put(c.point_step);
    w.put(c.row_step);
    w.put(uint32_t(c.data.size()));
    w.buf.insert(w.buf.end(), c.data.begin(), c.data.end());
    w.put(uint8_t(c.is_dense));
    return w.buf;
}

inline std::vector<uint8_t> cdr(const Imu& m) {
    CdrWriter w;
    w.header(m.stamp, m.frame);
    for (double v : {0.0, 0.0, 0.0, 1.0}) w.put(v);  // orientation
    for (int i = 0; i < 9; ++i) w.put(0.0);
    for (double v : m.gyro) w.put(v);
    for (int i = 0; i < 9; ++i) w.put(0.0);
    for (double v : m.acc) w.put(v);
    for (int i = 0; i < 9; ++i) w.put(0.0);
    return w.buf;
}

inline std::vector<uint8_t> cdr(const Odometry& m) {
    CdrWriter w;
    w.header(m.stamp, m.frame);
    w.str(m.child);
    w.pose(m.pose);
    for (double v : m.covariance) w.put(v);
    for (int i = 0; i < 6 + 36; ++i) w.put(0.0);  // twist
    return w.buf;
}

inline std::vector<uint8_t> cdr(const PoseStamped& m) {
    CdrWriter w;
    w.header(m.stamp, m.frame);
    w.pose(m.pose);
    return w.buf;
}

inline std::vector<uint8_t> cdr(const std::vector<Transform>& tf) {
    CdrWriter w;
    w.put(uint32_t(tf.size()));
    for (const auto& x : tf) {
        w.header(x.stamp, x.parent);
        w.str(x.child);
        w.pose(x.T);
    }
    return w.buf;
}

/// One message to write: topic, ROS 2 type name, bag time, CDR bytes.
struct Message {
    std::string topic, type;
    int64_t time_ns = 0;
    std::vector<uint8_t> data;
};

/// A rosbag2 SQLite file with the schema of rosbag2 (Humble+): topics, messages, schema,
/// metadata; the topics in order of first appearance. `page_size` 0 = SQLite's default (4096);
/// 512 makes the smallest files (fuzzing seeds).
inline void writeDb3(const std::string& path, const std::vector<Message>& msgs, int page_size = 0) {
    std::remove(path.c_str());
    sqlite3* db = nullptr;
    if (sqlite3_open(path.c_str(), &db) != SQLITE_OK)
        throw std::runtime_error("sqlite open " + path);
    const auto exec = [&](const std::string& sql) {
        char* err = nullptr;
        if (sqlite3_exec(db, sql.c_str(), nullptr, nullptr, &err) != SQLITE_OK) {
            const std::string e = err ? err : "?";
            sqlite3_free(err);
            throw std::runtime_error("sqlite: " + e);
        }
    };
    if (page_size > 0) exec("PRAGMA page_size=" + std::to_string(page_size) + ";");
    exec(
        "CREATE TABLE schema(schema_version INTEGER PRIMARY KEY, ros_distro TEXT NOT NULL);"
        "INSERT INTO schema VALUES(3, 'humble');"
        "CREATE TABLE metadata(id INTEGER PRIMARY KEY, metadata_version INTEGER NOT NULL,"
        " metadata TEXT NOT NULL);"
        "CREATE TABLE topics(id INTEGER PRIMARY KEY, name TEXT NOT NULL, type TEXT NOT NULL,"
        " serialization_format TEXT NOT NULL, offered_qos_profiles TEXT NOT NULL);"
        "CREATE TABLE messages(id INTEGER PRIMARY KEY, topic_id INTEGER NOT NULL,"
        " timestamp INTEGER NOT NULL, data BLOB NOT NULL);"
        "CREATE INDEX timestamp_idx ON messages (timestamp ASC);"
        "BEGIN;");
    std::map<std::string, int> ids;
    sqlite3_stmt* st = nullptr;
    sqlite3_prepare_v2(db, "INSERT INTO messages(topic_id, timestamp, data) VALUES(?, ?, ?)", -1,
                       &st, nullptr);
    for (const auto& m : msgs) {
        auto it = ids.find(m.topic);
        if (it == ids.end()) {
            it = ids.emplace(m.topic, int(ids.size()) + 1).first;
            exec("INSERT INTO topics VALUES(" + std::to_string(it->second) + ", '" + m.topic +
                 "', '" + m.type + "', 'cdr', '')");
        }
        sqlite3_bind_int(st, 1, it->second);
        sqlite3_bind_int64(st, 2, m.time_ns);
        sqlite3_bind_blob(st, 3, m.data.data(), int(m.data.size()), SQLITE_STATIC);
        if (sqlite3_step(st) != SQLITE_DONE) throw std::runtime_error("sqlite insert");
        sqlite3_reset(st);
    }
    sqlite3_finalize(st);
    exec("COMMIT;");
    sqlite3_close(db);
}

/// MCAP records, little endian.
class McapRecords {
 public:
    std::vector<uint8_t> out;
    template <class T>
    void num(std::vector<uint8_t>& b, T v) {
        for (size_t i = 0; i < sizeof(T); ++i) b.push_back(uint8_t(uint64_t(v) >> (8 * i)));
    }
    void str(std::vector<uint8_t>& b, const std::string& s) {
        num(b, uint32_t(s.size()));
        b.insert(b.end(), s.begin(), s.end());
    }
    void record(std::vector<uint8_t>& dst, uint8_t op, const std::vector<uint8_t>& content) {
        dst.push_back(op);
        num(dst, uint64_t(content.size()));
        dst.insert(dst.end(), content.begin(), content.end());
    }
};

struct McapOptions {
    /// "" (chunks stored uncompressed), "zstd", "lz4", any other string (written as is, with the
    /// records uncompressed: for unknown-compression tests), or "nochunks" (top-level messages)
    std::string compression = "zstd";
    size_t chunk_bytes = 1 << 20;  ///< a chunk is closed after this many uncompressed bytes
    bool crc = true;               ///< write the chunks' CRC-32 (else 0 = not given)
};

inline void writeMcap(const std::string& path, const std::vector<Message>& msgs,
                      const McapOptions& opt = {}) {
    McapRecords r;
    std::vector<uint8_t> file(reinterpret_cast<const uint8_t*>("\x89MCAP0\r\n"),
                              reinterpret_cast<const uint8_t*>("\x89MCAP0\r\n") + 8);
    std::vector<uint8_t> c;
    r.str(c, "ros2");
    r.str(c, "superloc-test");
    r.record(file, 0x01, c);
    std::map<std::string, uint16_t> schema, channel;
    std::vector<uint8_t> chunk;  // uncompressed records of the open chunk
    const bool chunked = opt.compression != "nochunks";
    const auto flush = [&] {
        if (chunk.empty()) return;
        std::vector<uint8_t> data = chunk;
        if (opt.compression == "zstd") {
            data.resize(ZSTD_compressBound(chunk.size()));
            data.resize(ZSTD_compress(data.data(), data.size(), chunk.data(), chunk.size(), 1));
        } else if (opt.compression == "lz4") {
            data.resize(LZ4F_compressFrameBound(chunk.size(), nullptr));
            data.resize(
                LZ4F_compressFrame(data.data(), data.size(), chunk.data(), chunk.size(), nullptr));
        }
        std::vector<uint8_t> k;
        r.num(k, uint64_t(0));  // message start/end time: not used by readers of the data section
        r.num(k, uint64_t(0));
        r.num(k, uint64_t(chunk.size()));
        r.num(k, uint32_t(opt.crc ? crc32(0, chunk.data(), uInt(chunk.size())) : 0));
        r.str(k, opt.compression);
        r.num(k, uint64_t(data.size()));
        k.insert(k.end(), data.begin(), data.end());
        r.record(file, 0x06, k);
        chunk.clear();
    };
    for (const auto& m : msgs) {
        std::vector<uint8_t>& dst = chunked ? chunk : file;
        if (!schema.count(m.type)) {
            const uint16_t id = uint16_t(schema.size() + 1);
            schema[m.type] = id;
            std::vector<uint8_t> s;
            r.num(s, id);
            r.str(s, m.type);
            r.str(s, "ros2msg");
            r.str(s, "# definition not needed by SuperLoc's reader");
            r.record(dst, 0x03, s);
        }
        if (!channel.count(m.topic)) {
            const uint16_t id = uint16_t(channel.size() + 1);
            channel[m.topic] = id;
            std::vector<uint8_t> s;
            r.num(s, id);
            r.num(s, schema[m.type]);
            r.str(s, m.topic);
            r.str(s, "cdr");
            r.num(s, uint32_t(0));  // metadata: empty map
            r.record(dst, 0x04, s);
        }
        std::vector<uint8_t> s;
        r.num(s, channel[m.topic]);
        r.num(s, uint32_t(0));
        r.num(s, uint64_t(m.time_ns));
        r.num(s, uint64_t(m.time_ns));
        s.insert(s.end(), m.data.begin(), m.data.end());
        r.record(dst, 0x05, s);
        if (chunked && chunk.size() >= opt.chunk_bytes) flush();
    }
    flush();
    std::vector<uint8_t> e;
    r.num(e, uint32_t(0));
    r.record(file, 0x0F, e);  // Data End
    std::vector<uint8_t> f;
    r.num(f, uint64_t(0));
    r.num(f, uint64_t(0));
    r.num(f, uint32_t(0));
    r.record(file, 0x02, f);  // Footer (no summary)
    file.insert(file.end(), reinterpret_cast<const uint8_t*>("\x89MCAP0\r\n"),
                reinterpret_cast<const uint8_t*>("\x89MCAP0\r\n") + 8);
    std::ofstream(path, std::ios::binary)
        .write(reinterpret_cast<const char*>(file.data()), std::streamsize(file.size()));
}

}  // namespace superloc::testing::bag
