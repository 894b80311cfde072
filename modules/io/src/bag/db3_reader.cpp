// ROS 2 bags in SQLite 3 (rosbag2's default storage before Iron, `.db3`), read through
// libsqlite3. The rosbag2 schema, as this reader uses it:
//   topics(id INTEGER PRIMARY KEY, name TEXT, type TEXT, serialization_format TEXT, ...)
//   messages(id INTEGER PRIMARY KEY, topic_id INTEGER, timestamp INTEGER [ns], data BLOB)
// (later versions add columns, a `schema` and a `metadata` table with the bag's YAML; neither
// is needed here). Messages are visited ordered by timestamp (then id); `data` is the CDR
// message (cdr.h). The database is opened read-only and never modified.
#include <sqlite3.h>

#include <map>
#include <stdexcept>

#include "bag_source.h"
#include "cdr.h"

namespace superloc::io::detail {

namespace {

class Db3Bag : public BagSource {
 public:
    explicit Db3Bag(const std::string& path) : path_(path) {
        try {
            if (sqlite3_open_v2(path.c_str(), &db_, SQLITE_OPEN_READONLY, nullptr) != SQLITE_OK)
                fail("cannot open");
            readTopics();
        } catch (...) {
            sqlite3_close(db_);
            throw;
        }
    }
    ~Db3Bag() override { sqlite3_close(db_); }
    const std::string& path() const override { return path_; }

    std::vector<BagTopic> topics() override {
        std::map<int64_t, size_t> counts;
        Statement s(*this, "SELECT topic_id, COUNT(*) FROM messages GROUP BY topic_id");
        while (s.step())
            counts[sqlite3_column_int64(s.st, 0)] = size_t(sqlite3_column_int64(s.st, 1));
        std::map<std::string, BagTopic> sorted;
        for (const auto& [id, t] : topics_) sorted[t.name] = {t.name, t.type, counts[id]};
        std::vector<BagTopic> out;
        for (auto& [name, t] : sorted) out.push_back(t);
        return out;
    }

    void forEach(const std::vector<std::string>& names,
                 const std::function<bool(const BagMessage&)>& fn) override {
        std::string ids;
        for (const auto& [id, t] : topics_)
            for (const auto& n : names)
                if (t.name == n) {
                    if (t.format != "cdr")
                        throw std::runtime_error(path_ + ": topic '" + n + "' is serialized as '" +
                                                 t.format + "'; only cdr is read");
                    ids += (ids.empty() ? "" : ",") + std::to_string(id);
                }
        if (ids.empty()) return;
        Statement s(*this, "SELECT topic_id, timestamp, data FROM messages WHERE topic_id IN (" +
                               ids + ") ORDER BY timestamp, id");
        while (s.step()) {
            const auto it = topics_.find(sqlite3_column_int64(s.st, 0));
            const auto* data = static_cast<const uint8_t*>(sqlite3_column_blob(s.st, 2));
            const size_t size = size_t(sqlite3_column_bytes(s.st, 2));
            const CdrMessage m(it->second.name, it->second.type, sqlite3_column_int64(s.st, 1),
                               data, size);
            if (!fn(m)) break;
        }
    }

 private:
    struct Topic {
        std::string name, type, format;
    };

    /// A prepared statement; step() is false at the end and throws on an SQLite error.
    struct Statement {
        Statement(Db3Bag& bag, const std::string& sql) : b(bag) {
            if (sqlite3_prepare_v2(b.db_, sql.c_str(), -1, &st, nullptr) != SQLITE_OK)
                b.fail(sqlite3_errcode(b.db_) == SQLITE_ERROR
                           ? "not a rosbag2 database (tables topics and messages)"
                           : "corrupt or truncated");
        }
        ~Statement() { sqlite3_finalize(st); }
        bool step() {
            const int rc = sqlite3_step(st);
            if (rc == SQLITE_ROW) return true;
            if (rc == SQLITE_DONE) return false;
            b.fail("corrupt or truncated");
        }
        Db3Bag& b;
        sqlite3_stmt* st = nullptr;
    };

    [[noreturn]] void fail(const std::string& what) const {
        // SQLite's messages may quote schema text with line breaks (found by fuzz_db3): keep
        // the error one line.
        std::string msg = db_ ? sqlite3_errmsg(db_) : "out of memory";
        for (char& c : msg)
            if (c == '\n' || c == '\r' || c == '\t') c = ' ';
        if (msg.size() > 200) msg = msg.substr(0, 200) + "...";
        throw std::runtime_error(path_ + ": ROS 2 bag (SQLite): " + what + ": " + msg);
    }

    static std::string text(sqlite3_stmt* st, int col) {
        const auto* p = sqlite3_column_text(st, col);
        return p ? reinterpret_cast<const char*>(p) : "";
    }

    void readTopics() {
        Statement s(*this, "SELECT id, name, type, serialization_format FROM topics");
        while (s.step())
            topics_[sqlite3_column_int64(s.st, 0)] = {text(s.st, 1), text(s.st, 2), text(s.st, 3)};
    }

    std::string path_;
    sqlite3* db_ = nullptr;
    std::map<int64_t, Topic> topics_;
};

}  // namespace

std::unique_ptr<BagSource> openDb3Bag(const std::string& path) {
    return std::make_unique<Db3Bag>(path);
}

}  // namespace superloc::io::detail
