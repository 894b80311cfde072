// Helpers shared by the SuperLoc test executables.
#pragma once

#include <gtest/gtest.h>

#include <cctype>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <stdexcept>
#include <string>

namespace superloc::testing {

/// What `f` throws (its what()), or "" when it does not throw: for one-line error checks.
inline std::string errorOf(const std::function<void()>& f) {
    try {
        f();
    } catch (const std::exception& e) {
        return e.what();
    }
    return "";
}

/// The whole content of a file ("" when it cannot be read).
inline std::string slurp(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

/// ../shared/data (or the SUPERLOC_SHARED_DATA CMake cache path) joined with `rel`.
inline std::string sharedData(const std::string& rel = "") {
    return (std::filesystem::path(SUPERLOC_SHARED_DATA) / rel).string();
}

/// A path in the source tree, e.g. sourcePath("ini/localize.ini").
inline std::string sourcePath(const std::string& rel) {
    return (std::filesystem::path(SUPERLOC_SOURCE_DIR) / rel).string();
}

/// Path of a built app, e.g. appPath("superloc-map") (all apps are built into build/bin).
inline std::string appPath(const std::string& app) {
    return (std::filesystem::path(SUPERLOC_BINARY_DIR) / "bin" / app).string();
}

/// A fresh, empty folder for one test's outputs (under the build tree), removed first if present.
/// CTest runs every test case in its own process (--gtest_filter=Suite.Case), in parallel, and a
/// suite-level fixture would otherwise share (and wipe) one folder across processes: the filter
/// is therefore part of the folder's name.
inline std::string freshDir(const std::string& name) {
    std::string tag = name;
    std::string filter = GTEST_FLAG_GET(filter);
    if (!filter.empty() && filter != "*") {
        for (char& c : filter)
            if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
        tag += "." + filter;
    }
    const auto dir = std::filesystem::path(SUPERLOC_BINARY_DIR) / "test-output" / tag;
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    return dir.string();
}

/// Skips the current test when the shared data set is missing (developer machines without
/// ../shared); CI always has it, so the test runs there.
#define SUPERLOC_REQUIRE_DATA(rel)                                                      \
    do {                                                                                \
        if (!std::filesystem::exists(::superloc::testing::sharedData(rel)))             \
            GTEST_SKIP() << "shared data not found: " << ::superloc::testing::sharedData(rel); \
    } while (0)

}  // namespace superloc::testing
