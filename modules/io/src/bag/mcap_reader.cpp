// MCAP files (rosbag2's default storage since Iron), read from the public format
// specification (mcap.dev/spec, major version 0), data section only:
//   file    = magic "\x89MCAP0\r\n", records..., magic
//   record  = opcode (uint8), content length (uint64), content
//   strings = uint32 byte length + bytes; maps/arrays = uint32 byte length + entries;
//   integers little endian
//   0x01 Header  {string profile, string library}
//   0x02 Footer  {uint64 summary_start, uint64 summary_offset_start, uint32 summary_crc}
//   0x03 Schema  {uint16 id, string name, string encoding, uint32-length data}
//   0x04 Channel {uint16 id, uint16 schema_id, string topic, string message_encoding,
//                 map<string,string> metadata}
//   0x05 Message {uint16 channel_id, uint32 sequence, uint64 log_time, uint64 publish_time,
//                 data = the rest of the record}
//   0x06 Chunk   {uint64 message_start_time, uint64 message_end_time, uint64 uncompressed_size,
//                 uint32 uncompressed_crc (CRC-32, 0 = not given), string compression
//                 ("" | "zstd" | "lz4" frame format), uint64-length records}
//   0x0F Data End ends the data section; the summary after it only repeats what came before.
// Schemas and channels precede the messages that use them, so one linear pass reads the file;
// every other record (indexes, attachments, metadata) is skipped. For ROS 2 the schema name is
// the type ("sensor_msgs/msg/PointCloud2") and the message encoding "cdr" (cdr.h).
//
// Order of a visit: chunks and top-level messages in file order, the messages of one chunk by
// log_time (stable); ROS 2's recorder writes chunks in time order.
#include <lz4frame.h>
#include <zlib.h>
#include <zstd.h>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <map>
#include <stdexcept>

#include "bag_source.h"
#include "cdr.h"

namespace superloc::io::detail {

namespace {

constexpr char kMagic[] = "\x89MCAP0\r\n";
constexpr uint64_t kMaxRecord = uint64_t(1) << 31;  ///< 2 GiB: larger records are refused
constexpr uint64_t kMaxChunk = uint64_t(1) << 31;   ///< decompressed chunk limit

/// Bounds-checked little-endian reads of one record's content.
class Fields {
 public:
    Fields(const uint8_t* p, uint64_t n, const std::string& where) : p_(p), n_(n), where_(where) {}
    template <class T>
    T num(const char* what) {
        T v = 0;
        for (size_t i = 0; i < sizeof(T); ++i) v |= T(T(take(1, what)[0]) << (8 * i));
        return v;
    }
    std::string str(const char* what) {
        const uint32_t n = num<uint32_t>(what);
        return std::string(reinterpret_cast<const char*>(take(n, what)), n);
    }
    const uint8_t* take(uint64_t n, const char* what) {
        if (n > n_ - pos_)
            throw std::runtime_error(where_ + ": " + what + " runs past the end of the record");
        const uint8_t* p = p_ + pos_;
        pos_ += n;
        return p;
    }
    uint64_t left() const { return n_ - pos_; }

 private:
    const uint8_t* p_;
    uint64_t n_, pos_ = 0;
    const std::string& where_;
};

class McapBag : public BagSource {
 public:
    explicit McapBag(const std::string& path) : path_(path) {
        in_.open(path, std::ios::binary);
        if (!in_) throw std::runtime_error(path + ": cannot open");
        in_.seekg(0, std::ios::end);
        file_size_ = uint64_t(in_.tellg());
    }
    const std::string& path() const override { return path_; }

    std::vector<BagTopic> topics() override {
        std::map<uint16_t, size_t> counts;
        scan(
            [&](uint16_t channel, uint64_t, const uint8_t*, uint64_t) {
                ++counts[channel];
                return true;
            },
            nullptr);
        std::map<std::string, BagTopic> sorted;
        for (const auto& [id, c] : channels_) {
            auto& t = sorted[c.topic];
            t.topic = c.topic;
            t.type = c.type;
            t.messages += counts[id];
        }
        std::vector<BagTopic> out;
        for (auto& [name, t] : sorted) out.push_back(t);
        return out;
    }

    void forEach(const std::vector<std::string>& topics,
                 const std::function<bool(const BagMessage&)>& fn) override {
        const auto wanted = [&](uint16_t channel) {
            const auto it = channels_.find(channel);
            return it != channels_.end() &&
                   std::find(topics.begin(), topics.end(), it->second.topic) != topics.end();
        };
        const auto visit = [&](uint16_t channel, uint64_t log_time, const uint8_t* data,
                               uint64_t size) {
            const Channel& c = channels_.at(channel);
            if (c.encoding != "cdr")
                throw std::runtime_error(path_ + ": topic '" + c.topic + "' is encoded as '" +
                                         c.encoding + "'; only cdr is read");
            return fn(CdrMessage(c.topic, c.type, int64_t(log_time), data, size_t(size)));
        };
        scan(
            [&](uint16_t channel, uint64_t log_time, const uint8_t* data, uint64_t size) {
                return !wanted(channel) || visit(channel, log_time, data, size);
            },
            [&](const std::vector<Pending>& chunk) {
                for (const Pending& m : chunk)
                    if (wanted(m.channel) && !visit(m.channel, m.log_time, m.data, m.size))
                        return false;
                return true;
            });
    }

 private:
    struct Channel {
        std::string topic, encoding, type;
    };
    struct Pending {  ///< a message of a chunk, waiting for the chunk's sort by log_time
        uint16_t channel;
        uint64_t log_time;
        const uint8_t* data;
        uint64_t size;
    };
    using MessageFn = std::function<bool(uint16_t, uint64_t, const uint8_t*, uint64_t)>;
    using ChunkFn = std::function<bool(const std::vector<Pending>&)>;

    [[noreturn]] void fail(const std::string& what) const {
        throw std::runtime_error(path_ + ": MCAP: " + what);
    }

    /// One linear pass over the data section. Top-level messages go to `on_message`; a chunk's
    /// messages go to `on_chunk` sorted by log time (or one by one to `on_message` when
    /// `on_chunk` is null). Either returning false ends the pass.
    void scan(const MessageFn& on_message, const ChunkFn& on_chunk) {
        in_.clear();
        in_.seekg(0);
        char magic[8];
        if (!in_.read(magic, 8) || std::memcmp(magic, kMagic, 8) != 0)
            fail("does not start with the MCAP magic bytes");
        uint64_t offset = 8;
        for (;;) {
            uint8_t head[9];
            if (!in_.read(reinterpret_cast<char*>(head), 9))
                fail("truncated: the file ends at byte " + std::to_string(offset) +
                     " without a Data End or Footer record");
            uint64_t len = 0;
            for (int i = 0; i < 8; ++i) len |= uint64_t(head[1 + i]) << (8 * i);
            const std::string where =
                "record 0x" + hex(head[0]) + " at byte " + std::to_string(offset);
            if (len > file_size_ - offset - 9 || len > kMaxRecord)
                fail("truncated: " + where + " says " + std::to_string(len) +
                     " bytes, more than the file holds");
            record_.resize(size_t(len));
            if (len > 0 && !in_.read(reinterpret_cast<char*>(record_.data()), std::streamsize(len)))
                fail("truncated: " + where + " cannot be read");
            offset += 9 + len;
            const uint8_t op = head[0];
            if (op == 0x02 || op == 0x0F) return;  // Footer / Data End
            if (op == 0x06) {
                if (!readChunk(where, on_message, on_chunk)) return;
            } else if (!readRecord(op, record_.data(), len, where, on_message, nullptr)) {
                return;
            }
        }
    }

    /// Schema, channel or message (others are skipped); false when the visit should end.
    bool readRecord(uint8_t op, const uint8_t* p, uint64_t len, const std::string& where,
                    const MessageFn& on_message, std::vector<Pending>* pending) {
        const std::string full = path_ + ": MCAP: " + where;
        Fields f(p, len, full);
        if (op == 0x03) {
            const auto id = f.num<uint16_t>("schema id");
            const std::string name = f.str("schema name");
            f.str("schema encoding");
            schemas_[id] = name;
        } else if (op == 0x04) {
            const auto id = f.num<uint16_t>("channel id");
            const auto schema = f.num<uint16_t>("channel schema_id");
            Channel c;
            c.topic = f.str("channel topic");
            c.encoding = f.str("channel message_encoding");
            if (schema != 0) {
                const auto it = schemas_.find(schema);
                if (it == schemas_.end())
                    throw std::runtime_error(path_ + ": MCAP: " + where + ": channel '" + c.topic +
                                             "' uses schema " + std::to_string(schema) +
                                             ", which no earlier Schema record defines");
                c.type = it->second;
            }
            channels_[id] = c;
        } else if (op == 0x05) {
            const auto channel = f.num<uint16_t>("message channel_id");
            f.num<uint32_t>("message sequence");
            const auto log_time = f.num<uint64_t>("message log_time");
            f.num<uint64_t>("message publish_time");
            if (!channels_.count(channel))
                throw std::runtime_error(path_ + ": MCAP: " + where + ": message on channel " +
                                         std::to_string(channel) +
                                         ", which no earlier Channel record defines");
            const uint64_t n = f.left();
            const uint8_t* data = f.take(n, "message data");
            if (pending) {
                pending->push_back({channel, log_time, data, n});
                return true;
            }
            return on_message(channel, log_time, data, n);
        }
        return true;
    }

    bool readChunk(const std::string& where, const MessageFn& on_message, const ChunkFn& on_chunk) {
        const std::string full = path_ + ": MCAP: " + where;
        Fields f(record_.data(), record_.size(), full);
        f.num<uint64_t>("chunk message_start_time");
        f.num<uint64_t>("chunk message_end_time");
        const auto usize = f.num<uint64_t>("chunk uncompressed_size");
        const auto crc = f.num<uint32_t>("chunk uncompressed_crc");
        const std::string compression = f.str("chunk compression");
        const auto csize = f.num<uint64_t>("chunk records length");
        const uint8_t* src = f.take(csize, "chunk records");
        const std::string cwhere =
            path_ + ": MCAP: chunk (" + where + ", compression '" + printable(compression) + "')";
        if (compression != "" && compression != "zstd" && compression != "lz4")
            throw std::runtime_error(cwhere + ": unknown compression (known: '', zstd, lz4)");
        if (usize > kMaxChunk || (compression != "" && usize > csize * 4096 + (1 << 20)))
            throw std::runtime_error(cwhere + ": implausible uncompressed_size " +
                                     std::to_string(usize));
        const uint8_t* records = src;
        if (compression == "") {
            if (usize != csize)
                throw std::runtime_error(cwhere + ": uncompressed_size " + std::to_string(usize) +
                                         " is not the records length " + std::to_string(csize));
        } else {
            chunk_.resize(size_t(usize));
            const size_t got =
                compression == "zstd" ? unzstd(src, csize, cwhere) : unlz4(src, csize, cwhere);
            if (got != usize)
                throw std::runtime_error(cwhere + ": decompresses to " + std::to_string(got) +
                                         " bytes, not its uncompressed_size " +
                                         std::to_string(usize));
            records = chunk_.data();
        }
        if (crc != 0 && uint32_t(crc32_z(crc32_z(0, nullptr, 0), records, size_t(usize))) != crc)
            throw std::runtime_error(cwhere + ": CRC mismatch (corrupt chunk)");
        // The chunk's own records: schemas, channels, messages.
        std::vector<Pending> pending;
        for (uint64_t pos = 0; pos < usize;) {
            if (usize - pos < 9)
                throw std::runtime_error(cwhere + ": record header at chunk byte " +
                                         std::to_string(pos) + " runs past the chunk");
            uint64_t len = 0;
            for (int i = 0; i < 8; ++i) len |= uint64_t(records[pos + 1 + i]) << (8 * i);
            const std::string rwhere = where + ", chunk record 0x" + hex(records[pos]) +
                                       " at chunk byte " + std::to_string(pos);
            if (len > usize - pos - 9)
                throw std::runtime_error(path_ + ": MCAP: " + rwhere + " runs past the chunk");
            if (!readRecord(records[pos], records + pos + 9, len, rwhere, on_message,
                            on_chunk ? &pending : nullptr))
                return false;
            pos += 9 + len;
        }
        if (!on_chunk) return true;
        std::stable_sort(pending.begin(), pending.end(), [](const Pending& a, const Pending& b) {
            return a.log_time < b.log_time;
        });
        return on_chunk(pending);
    }

    size_t unzstd(const uint8_t* src, uint64_t n, const std::string& where) {
        const size_t r = ZSTD_decompress(chunk_.data(), chunk_.size(), src, size_t(n));
        if (ZSTD_isError(r)) throw std::runtime_error(where + ": zstd: " + ZSTD_getErrorName(r));
        return r;
    }

    size_t unlz4(const uint8_t* src, uint64_t n, const std::string& where) {
        LZ4F_dctx* ctx = nullptr;
        if (LZ4F_isError(LZ4F_createDecompressionContext(&ctx, LZ4F_VERSION)))
            throw std::runtime_error(where + ": lz4: cannot create a decompression context");
        size_t out = 0, in = 0;
        size_t hint = 1;
        while (in < n && hint != 0) {
            size_t dst_size = chunk_.size() - out, src_size = size_t(n) - in;
            hint =
                LZ4F_decompress(ctx, chunk_.data() + out, &dst_size, src + in, &src_size, nullptr);
            if (LZ4F_isError(hint)) {
                LZ4F_freeDecompressionContext(ctx);
                throw std::runtime_error(where + ": lz4: " + LZ4F_getErrorName(hint));
            }
            out += dst_size;
            in += src_size;
            if (dst_size == 0 && src_size == 0) break;  // output full: no progress possible
        }
        LZ4F_freeDecompressionContext(ctx);
        if (hint != 0)
            throw std::runtime_error(where +
                                     ": lz4: the frame is truncated or larger than "
                                     "uncompressed_size");
        return out;
    }

    static std::string hex(uint8_t b) {
        const char* d = "0123456789abcdef";
        return {d[b >> 4], d[b & 15]};
    }

    std::string path_;
    std::ifstream in_;
    uint64_t file_size_ = 0;
    std::vector<uint8_t> record_, chunk_;
    std::map<uint16_t, std::string> schemas_;
    std::map<uint16_t, Channel> channels_;
};

}  // namespace

std::unique_ptr<BagSource> openMcapBag(const std::string& path) {
    return std::make_unique<McapBag>(path);
}

}  // namespace superloc::io::detail
