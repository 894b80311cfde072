// JSON files (summary.json, eval --json, bench results.json) through nlohmann::json.
//
// JSON has no NaN or infinity: every non-finite number becomes null, and each one is reported as
// a warning naming its place in the document (a JSON pointer, e.g. "/ate_rmse_vs_rawlog_gt").
#pragma once

#include <nlohmann/json_fwd.hpp>

#include <string>
#include <vector>

namespace mrpt::system {
class COutputLogger;
}

namespace superloc::io {

/// A JSON document that keeps its keys in insertion order (the files read like their structs).
using Json = nlohmann::ordered_json;

/// Replaces every NaN/inf number of `j` (at any depth) by null; returns the JSON pointers of
/// the replaced values, in document order.
std::vector<std::string> replaceNonFinite(Json& j);

/// `j` as pretty-printed JSON (2-space indent, final newline), non-finite numbers written as
/// null; each of those is logged as a warning on `log` (the io module's logger when null),
/// naming `what` (e.g. the file).
std::string toJsonText(const Json& j, const std::string& what = "JSON",
                       mrpt::system::COutputLogger* log = nullptr);

/// Writes toJsonText(j) to `path`. Throws std::runtime_error naming the path when it cannot.
void saveJson(const std::string& path, const Json& j,
              mrpt::system::COutputLogger* log = nullptr);

/// Parses a JSON file. Throws std::runtime_error with a one-line message naming the path on a
/// missing or malformed file.
Json loadJson(const std::string& path);

}  // namespace superloc::io
