// A small streaming JSON writer (pretty-printed; NaN/inf are written as null).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace superloc::eval {

class JsonWriter {
 public:
    JsonWriter& beginObject();
    JsonWriter& endObject();
    JsonWriter& beginArray();
    JsonWriter& endArray();
    /// The next member's name (inside an object).
    JsonWriter& key(const std::string& k);
    JsonWriter& value(double v);
    JsonWriter& value(int64_t v);
    JsonWriter& value(size_t v) { return value(static_cast<int64_t>(v)); }
    JsonWriter& value(int v) { return value(static_cast<int64_t>(v)); }
    JsonWriter& value(bool v);
    JsonWriter& value(const std::string& v);
    JsonWriter& value(const char* v) { return value(std::string(v)); }
    JsonWriter& null();
    JsonWriter& array(const std::vector<double>& v);
    /// key(k).value(v) in one call.
    template <class T>
    JsonWriter& field(const std::string& k, const T& v) {
        return key(k).value(v);
    }

    /// The document so far (complete once every object/array is closed).
    const std::string& str() const { return out_; }

 private:
    void beforeValue();
    JsonWriter& close(char bracket);
    void newline();
    std::string out_;
    std::vector<bool> first_;  ///< per open container: no element written yet
    bool after_key_ = false;
};

/// s with JSON string escapes, without the quotes.
std::string jsonEscape(const std::string& s);

}  // namespace superloc::eval
