// Shared by the libFuzzer targets (tests/fuzz/fuzz_*.cpp, built with -DSUPERLOC_FUZZ=ON).
//
// The readers' contract (doc/io.md): on any input they either load or throw one std::exception
// whose message is one line. Anything else — a crash, a sanitizer report, another exception
// type, a multi-line message — is a finding: the target aborts so libFuzzer keeps the input.
#pragma once

#include <superloc/io/point_cloud_io.h>

#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <string>

namespace superloc::fuzz {

/// A per-process scratch file with extension `ext` (the readers pick the format by it), in
/// /dev/shm when available (memory-backed: no disk traffic per execution).
inline const std::string& scratchPath(const char* ext) {
    static const std::string path = [ext] {
        const std::filesystem::path dir = std::filesystem::exists("/dev/shm")
                                              ? std::filesystem::path("/dev/shm")
                                              : std::filesystem::temp_directory_path();
        return (dir / ("superloc-fuzz-" + std::to_string(::getpid()) + ext)).string();
    }();
    return path;
}

/// Writes the fuzzer's bytes to `path`.
inline void writeBytes(const std::string& path, const uint8_t* data, size_t size) {
    std::ofstream f(path, std::ios::binary | std::ios::trunc);
    f.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
    if (!f) {
        std::fprintf(stderr, "fuzz: cannot write %s\n", path.c_str());
        std::abort();
    }
}

/// Runs `load`; a std::exception with a one-line message is an accepted outcome.
template <class F>
void expectLoadsOrThrowsOneLine(F&& load) {
    try {
        load();
    } catch (const std::exception& e) {
        const std::string msg = e.what();
        if (msg.empty() || msg.find('\n') != std::string::npos) {
            std::fprintf(stderr, "fuzz: error message is not one line: <<%s>>\n", msg.c_str());
            std::abort();
        }
    }
}

/// One point-cloud input: the bytes as a file with extension `ext`, read by io::loadPointCloud;
/// it loads with consistent attributes (absent or one per point) or throws one line.
inline int fuzzPointCloudFile(const char* ext, const uint8_t* data, size_t size) {
    const std::string& path = scratchPath(ext);
    writeBytes(path, data, size);
    expectLoadsOrThrowsOneLine([&] {
        size_t dropped = 0;
        const PointCloud c = io::loadPointCloud(path, io::CloudFormat::Auto, &dropped);
        if ((!c.intensity.empty() && c.intensity.size() != c.size()) ||
            (!c.normals.empty() && c.normals.size() != c.size()) || (!c.rgb.empty() && c.rgb.size() != c.size()))
            std::abort();
    });
    return 0;
}

}  // namespace superloc::fuzz
