// The bad-input battery (issue 36): each of the six apps given one broken input (a truncated,
// bit-flipped or foreign rawlog, a broken PCD/PLY/TUM/INI/CSV/KITTI/bag file, a bad flag, an
// unwritable output) must stop with a non-zero exit code and one line that names the culprit
// (the file and line, the section or the key), or, where the input is legal but surprising, run
// and say so in one warning line. Every case runs the real executable on the tiny fixtures of
// rawlogs/ (a few hundred ms each). CONTRIBUTING.md "Bad input" says how a new reader or option
// gets its cases here.
#include <gtest/gtest.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <nlohmann/json.hpp>
#include <mrpt/io/CMemoryStream.h>
#include <mrpt/obs/CObservationPointCloud.h>
#include <mrpt/serialization/CArchive.h>
#include <superloc/app/process.h>
#include <superloc/io/tum.h>
#include <superloc_testing/testing.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <optional>
#include <random>
#include <sstream>

namespace fs = std::filesystem;
using superloc::testing::appPath;
using superloc::testing::sourcePath;

namespace {

std::string slurp(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

void write(const std::string& path, const std::string& text) {
    std::ofstream(path, std::ios::binary) << text;
}

std::vector<std::string> lines(const std::string& s) {
    std::vector<std::string> out;
    std::istringstream in(s);
    for (std::string l; std::getline(in, l);)
        if (!l.empty() && l.find_first_not_of(" \t\r") != std::string::npos) out.push_back(l);
    return out;
}

// The tiny fixtures: 10 scans of a simulated office, its prior map and ground truth.
const std::string kRawlog = sourcePath("rawlogs/office-tiny.rawlog");
const std::string kMap = sourcePath("rawlogs/office-tiny-map.pcd");
const std::string kGt = sourcePath("rawlogs/office-tiny-gt.tum");
const std::string kIni = sourcePath("ini/localize.ini");

/// The rawlog's bytes uncompressed (the reader takes plain and gzip rawlogs alike), and the
/// byte span of each entry that is a LiDAR scan.
struct PlainRawlog {
    std::string bytes;
    std::vector<std::pair<size_t, size_t>> scans;  // [begin, end) of each scan entry
};

PlainRawlog plainRawlog() {
    PlainRawlog r;
    mrpt::io::CFileGZInputStream in(kRawlog);
    char buf[65536];
    for (size_t n; (n = in.Read(buf, sizeof buf)) > 0;) r.bytes.append(buf, n);
    mrpt::io::CMemoryStream mem;
    mem.assignMemoryNotOwn(r.bytes.data(), r.bytes.size());
    auto arch = mrpt::serialization::archiveFrom(mem);
    while (static_cast<size_t>(mem.getPosition()) < r.bytes.size()) {
        const size_t begin = mem.getPosition();
        mrpt::serialization::CSerializable::Ptr obj;
        arch >> obj;
        if (std::dynamic_pointer_cast<mrpt::obs::CObservationPointCloud>(obj))
            r.scans.emplace_back(begin, mem.getPosition());
    }
    return r;
}

/// What one case gives an app: its arguments, built in the case's own folder `d`.
using Args = std::function<std::vector<std::string>(const std::string& d)>;

struct BadInput {
    std::string name;                 // the test's name
    std::string app;                  // e.g. "superloc-localize"
    Args args;                        // the command line (files written into d)
    int exit_code;                    // 1 for an error, 0 for a warning
    std::vector<std::string> expect;  // what the error (or warning) line must say
};

std::ostream& operator<<(std::ostream& os, const BadInput& c) { return os << c.name; }

/// superloc-localize on the tiny fixtures, `config` written as the INI (empty: ini/localize.ini).
std::vector<std::string> localize(const std::string& d, const std::string& config,
                                  std::vector<std::string> extra = {}, const std::string& rawlog = kRawlog,
                                  const std::string& map = kMap) {
    std::string ini = kIni;
    if (!config.empty()) write(ini = d + "/loc.ini", config);
    std::vector<std::string> a = {ini, "--rawlog", rawlog, "--map", map, "--initial-pose-tum", kGt,
                                  "--out", d + "/out", "--quiet"};
    a.insert(a.end(), extra.begin(), extra.end());
    return a;
}

const std::string kPcdHead =
    "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 3\nHEIGHT 1\n"
    "VIEWPOINT 0 0 0 1 0 0 0\nPOINTS 3\nDATA ascii\n";

/// A KITTI folder of three scans (16 bytes per point: x y z intensity) in d/kitti; the second
/// scan's file is `second` (a valid one when empty).
std::string kitti(const std::string& d, const std::optional<std::string>& second = std::nullopt,
                  const std::string& times = "0.0\n0.1\n0.2\n") {
    const std::string k = d + "/kitti";
    fs::create_directories(k + "/velodyne");
    std::string scan;
    for (int i = 0; i < 200; ++i) {
        const float p[4] = {float(i % 20), float(i / 20), 1.0f, 0.5f};
        scan.append(reinterpret_cast<const char*>(p), sizeof p);
    }
    for (int i = 0; i < 3; ++i)
        write(k + "/velodyne/00000" + std::to_string(i) + ".bin", i == 1 && second ? *second : scan);
    write(k + "/times.txt", times);
    return k;
}

const std::string kTum3 = "0.0 0 0 0 0 0 0 1\n0.1 1 0 0 0 0 0 1\n0.2 2 0 0 0 0 0 1\n";

std::vector<BadInput> cases() {
    const std::string L = "superloc-localize", M = "superloc-map", I = "superloc-import", E = "superloc-eval",
                      S = "superloc-sim", B = "superloc-bench";
    const auto ini = [](std::string text) {
        return [text](const std::string& d) { return localize(d, text); };
    };
    std::vector<BadInput> c;
    // ---- superloc-localize: the INI and --set (issue 36, cases 1 and 7) ----
    c.push_back({"LocalizeMisspeltSection", L, ini("[run]\n[localisation]\nmethod = icp\n"), 1,
                 {"loc.ini:2: unknown section [localisation]", "[localization]"}});
    c.push_back({"LocalizeSectionWithoutBracket", L, ini("[localization\nmethod = icp\n"), 1,
                 {"loc.ini:1:", "'[localization' has no closing ']'"}});
    c.push_back({"LocalizeKeyBeforeAnySection", L, ini("method = icp\n[localization]\n"), 1,
                 {"loc.ini:1:", "key 'method' before any [section]"}});
    c.push_back({"LocalizeSetUnknownSection", L,
                 [](const std::string& d) { return localize(d, "", {"--set", "localisation.method=icp"}); }, 1,
                 {"--set 'localisation.method=icp'", "no section [localisation]"}});
    c.push_back({"LocalizeDuplicateKey", L, ini("[localization]\nmethod = icp\nmethod = superloc\n"), 1,
                 {"loc.ini:3:", "[localization] method is given twice (also on line 2)"}});
    c.push_back({"LocalizeFractionForWholeNumber", L, ini("[localization]\nrounds = 2000.7\n"), 1,
                 {"[localization] rounds = '2000.7' is not a whole number"}});
    c.push_back({"LocalizeLineWithoutEquals", L, ini("[localization]\nmethod icp\n"), 1,
                 {"loc.ini:2:", "'method icp' is not key = value"}});
    c.push_back({"LocalizeUnknownKey", L, ini("[localization]\nmetod = icp\n"), 1,
                 {"unknown key 'metod' in section [localization]"}});
    c.push_back({"LocalizeNotABoolean", L,
                 [](const std::string& d) { return localize(d, "", {"--set", "features.deskew=maybe"}); }, 1,
                 {"[features] deskew = 'maybe' is not a boolean"}});
    c.push_back({"LocalizeEmptyMethod", L, [](const std::string& d) { return localize(d, "", {"--method", ""}); },
                 1, {"--method", "method = '' is unknown"}});
    c.push_back({"LocalizeUnknownMethod", L,
                 [](const std::string& d) { return localize(d, "", {"--method", "icpp"}); }, 1,
                 {"--method", "'icpp' is unknown"}});
    c.push_back({"LocalizeSetWithoutValue", L,
                 [](const std::string& d) { return localize(d, "", {"--set", "localization.method"}); }, 1,
                 {"--set 'localization.method'", "section.key=value"}});
    c.push_back({"LocalizeUnknownFlag", L, [](const std::string& d) { return localize(d, "", {"--bogus"}); }, 1,
                 {"--bogus"}});
    // ---- superloc-localize: the rawlog (cases 2 and 7) ----
    c.push_back({"LocalizeWrongLidarLabel", L,
                 [](const std::string& d) { return localize(d, "", {"--set", "rawlog.lidar_label=velodyne"}); }, 1,
                 {"office-tiny.rawlog", "lidar_label = 'velodyne'", "labelled 'lidar'"}});
    c.push_back({"LocalizeScansSelectNone", L,
                 [](const std::string& d) { return localize(d, "", {"--set", "rawlog.scans=100:"}); }, 1,
                 {"office-tiny.rawlog", "[rawlog] scans = '100:' selects none of its 10 LiDAR scans"}});
    c.push_back({"LocalizeRandomBytesRawlog", L,
                 [](const std::string& d) {
                     std::mt19937 rng(7);
                     std::string junk(4096, '\0');
                     for (char& ch : junk) ch = static_cast<char>(rng());
                     write(d + "/junk.rawlog", junk);
                     return localize(d, "", {}, d + "/junk.rawlog");
                 },
                 1, {"junk.rawlog: not an MRPT rawlog"}});
    c.push_back({"LocalizeTextFileAsRawlog", L,
                 [](const std::string& d) {
                     write(d + "/notes.rawlog", "these are my notes, not a rawlog\n");
                     return localize(d, "", {}, d + "/notes.rawlog");
                 },
                 1, {"notes.rawlog: not an MRPT rawlog"}});
    c.push_back({"LocalizeMissingRawlog", L,
                 [](const std::string& d) { return localize(d, "", {}, d + "/none.rawlog"); }, 1,
                 {"none.rawlog: rawlog not found"}});
    c.push_back({"LocalizeCorruptEntry", L,
                 [](const std::string& d) {
                     PlainRawlog r = plainRawlog();
                     // One bit of the class name of the 6th scan's entry: CObservation... -> BObservation...
                     // (its namespace is not checked: MRPT finds the class by its last part).
                     const size_t at = r.bytes.find("CObservationPointCloud", r.scans.at(5).first);
                     EXPECT_LT(at, r.scans.at(5).second);
                     r.bytes[at] ^= 0x01;
                     write(d + "/flipped.rawlog", r.bytes);
                     return localize(d, "", {}, d + "/flipped.rawlog");
                 },
                 1, {"flipped.rawlog: entry", "corrupt or truncated rawlog", "BObservationPointCloud"}});
    // ---- superloc-localize: the map, the initial pose, the outputs ----
    c.push_back({"LocalizeMissingMap", L,
                 [](const std::string& d) { return localize(d, "", {}, kRawlog, d + "/none.pcd"); }, 1,
                 {"none.pcd: map file not found"}});
    c.push_back({"LocalizePcdWordForNumber", L,
                 [](const std::string& d) {
                     write(d + "/map.pcd", kPcdHead + "1 2 3\n4 five 6\n7 8 9\n");
                     return localize(d, "", {}, kRawlog, d + "/map.pcd");
                 },
                 1, {"map.pcd:13: 'five' is not a number"}});
    c.push_back({"LocalizeNegativeMapVoxel", L,
                 [](const std::string& d) { return localize(d, "", {"--set", "map.voxel_size=-1"}); }, 1,
                 {"[map] voxel_size must be >= 0"}});
    c.push_back({"LocalizePointsBelowGammaOutOfRange", L,
                 [](const std::string& d) { return localize(d, "", {"--set", "association.points_below_gamma=1.5"}); },
                 1, {"[association] points_below_gamma must be in [0, 1]"}});
    c.push_back({"LocalizeNegativeLastScanFeatures", L,
                 [](const std::string& d) { return localize(d, "", {"--set", "localization.last_scan_features=-5"}); },
                 1, {"[localization] last_scan_features must be >= 0"}});
    c.push_back({"LocalizeNegativeHypothesisFeatures", L,
                 [](const std::string& d) { return localize(d, "", {"--set", "relocalization.hypothesis_features=-1"}); },
                 1, {"[relocalization] hypothesis_features must be >= 0"}});
    c.push_back({"LocalizeNegativeDoubtSearchPeriod", L,
                 [](const std::string& d) { return localize(d, "", {"--set", "relocalization.doubt_search_period=-0.5"}); },
                 1, {"[relocalization] doubt_search_period must be >= 0 s"}});
    c.push_back({"LocalizeTumRepeatedTime", L,
                 [](const std::string& d) {
                     write(d + "/start.tum", "0.0 0 0 0 0 0 0 1\n0.0 1 0 0 0 0 0 1\n");
                     auto a = localize(d, "");
                     a[6] = d + "/start.tum";  // --initial-pose-tum
                     return a;
                 },
                 1, {"start.tum:2: timestamp 0.0 repeats line 1"}});
    c.push_back({"LocalizeBadInitialPose", L,
                 [](const std::string& d) {
                     auto a = localize(d, "");
                     a.erase(a.begin() + 5, a.begin() + 7);
                     a.insert(a.end(), {"--initial-pose", "1 2 3"});
                     return a;
                 },
                 1, {"--initial-pose", "expected 7 numbers"}});
    c.push_back({"LocalizeOutIsAFile", L,
                 [](const std::string& d) {
                     write(d + "/file", "x");
                     auto a = localize(d, "");
                     a[8] = d + "/file";  // --out
                     return a;
                 },
                 1, {"file"}});
    // ---- superloc-map ----
    c.push_back({"MapSetUnknownSection", M,
                 [](const std::string& d) {
                     return std::vector<std::string>{"--rawlog", kRawlog, "--out", d + "/m.pcd", "--set", "rawlg.scans=even"};
                 },
                 1, {"--set 'rawlg.scans=even'", "superloc-map has no section [rawlg]", "[rawlog]"}});
    c.push_back({"MapConfigUnknownSection", M,
                 [](const std::string& d) {
                     write(d + "/m.ini", "; labels\n[rawlg]\nscans = even\n");
                     return std::vector<std::string>{"--rawlog", kRawlog, "--out", d + "/m.pcd", "--config", d + "/m.ini"};
                 },
                 1, {"m.ini:2: unknown section [rawlg]"}});
    c.push_back({"MapWrongLidarLabel", M,
                 [](const std::string& d) {
                     return std::vector<std::string>{"--rawlog", kRawlog, "--out", d + "/m.pcd", "--set",
                                                     "rawlog.lidar_label=velodyne"};
                 },
                 1, {"lidar_label = 'velodyne'"}});
    c.push_back({"MapRandomBytesRawlog", M,
                 [](const std::string& d) {
                     write(d + "/junk.rawlog", std::string(3000, '\x7f'));
                     return std::vector<std::string>{"--rawlog", d + "/junk.rawlog", "--out", d + "/m.pcd"};
                 },
                 1, {"junk.rawlog: not an MRPT rawlog"}});
    c.push_back({"MapPosesRepeatedTime", M,
                 [](const std::string& d) {
                     write(d + "/p.tum", "# poses\n1.0 0 0 0 0 0 0 1\n1.0 0 0 0 0 0 0 1\n");
                     return std::vector<std::string>{"--rawlog", kRawlog, "--poses", d + "/p.tum", "--out", d + "/m.pcd"};
                 },
                 1, {"p.tum:3: timestamp 1.0 repeats line 2"}});
    c.push_back({"MapPcdShortLine", M,
                 [](const std::string& d) {
                     write(d + "/in.pcd", kPcdHead + "1.25 2.25 3.25\n4.25 5.25\n7.25 8.25 9.25\n");
                     return std::vector<std::string>{"--from-map", d + "/in.pcd", "--out", d + "/m.pcd"};
                 },
                 1, {"in.pcd:13: 2 values", "say 3"}});
    c.push_back({"MapPcdMoreDataThanPoints", M,
                 [](const std::string& d) {
                     write(d + "/in.pcd", kPcdHead + "1 2 3\n4 5 6\n7 8 9\n10 11 12\n");
                     return std::vector<std::string>{"--from-map", d + "/in.pcd", "--out", d + "/m.pcd"};
                 },
                 1, {"in.pcd:15: more data lines than the header's 3 points"}});
    c.push_back({"MapPcdFewerLinesThanPoints", M,
                 [](const std::string& d) {
                     write(d + "/in.pcd", kPcdHead + "1.25 2.25 3.25\n4.25 5.25 6.25\n");
                     return std::vector<std::string>{"--from-map", d + "/in.pcd", "--out", d + "/m.pcd"};
                 },
                 1, {"in.pcd", "2 data lines for 3 points"}});
    c.push_back({"MapBinaryPcdMoreDataThanPoints", M,
                 [](const std::string& d) {
                     std::string pcd =
                         "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 2\nHEIGHT 1\n"
                         "POINTS 2\nDATA binary\n";
                     const float v[9] = {1, 2, 3, 4, 5, 6, 7, 8, 9};
                     pcd.append(reinterpret_cast<const char*>(v), sizeof v);
                     write(d + "/in.pcd", pcd);
                     return std::vector<std::string>{"--from-map", d + "/in.pcd", "--out", d + "/m.pcd"};
                 },
                 1, {"in.pcd", "the data holds 3 points", "says 2"}});
    c.push_back({"MapPlyWordForNumber", M,
                 [](const std::string& d) {
                     write(d + "/in.ply",
                           "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
                           "property float z\nend_header\n1 2 3\n4 x 6\n");
                     return std::vector<std::string>{"--from-map", d + "/in.ply", "--out", d + "/m.pcd"};
                 },
                 1, {"in.ply"}});
    c.push_back({"MapNegativeVoxel", M,
                 [](const std::string& d) {
                     return std::vector<std::string>{"--rawlog", kRawlog, "--voxel", "-1", "--out", d + "/m.pcd"};
                 },
                 1, {"voxel"}});
    c.push_back({"MapUnknownOutputFormat", M,
                 [](const std::string& d) {
                     return std::vector<std::string>{"--rawlog", kRawlog, "--out", d + "/m.las"};
                 },
                 1, {"m.las", "unknown point-cloud extension"}});
    // ---- superloc-import ----
    c.push_back({"ImportSetUnknownSection", I,
                 [](const std::string& d) {
                     return std::vector<std::string>{"--kitti", kitti(d), "--out", d + "/o.rawlog", "--set",
                                                     "rosbg.gt_topic=/gt"};
                 },
                 1, {"--set 'rosbg.gt_topic=/gt'", "superloc-import has no section [rosbg]"}});
    c.push_back({"ImportConfigDuplicateKey", I,
                 [](const std::string& d) {
                     write(d + "/i.ini", "[rosbag]\ngt_topic = /a\n\ngt_topic = /b\n");
                     return std::vector<std::string>{"--kitti", kitti(d), "--out", d + "/o.rawlog", "--config", d + "/i.ini"};
                 },
                 1, {"i.ini:4:", "[rosbag] gt_topic is given twice (also on line 2)"}});
    c.push_back({"ImportKittiBadTime", I,
                 [](const std::string& d) {
                     return std::vector<std::string>{"--kitti", kitti(d, std::nullopt, "0.0\n0.1s\n0.2\n"), "--out",
                                                     d + "/o.rawlog"};
                 },
                 1, {"times.txt:2", "0.1s"}});
    c.push_back({"ImportKittiPartialPoint", I,
                 [](const std::string& d) {
                     return std::vector<std::string>{"--kitti", kitti(d, std::string(20, '\0')), "--out", d + "/o.rawlog"};
                 },
                 1, {"000001.bin"}});
    c.push_back({"ImportKittiEmptyScanWarns", I,
                 [](const std::string& d) {
                     return std::vector<std::string>{"--kitti", kitti(d, std::string()), "--out", d + "/o.rawlog", "--quiet"};
                 },
                 0, {"warning: 1 empty scan", "000001.bin"}});
    c.push_back({"ImportImuCsvBadLine", I,
                 [](const std::string& d) {
                     write(d + "/imu.csv", "t,ax,ay,az,wx,wy,wz\n0.0,0,0,9.8,0,0,0\n0.1,0,0,9.8,0,zero,0\n");
                     return std::vector<std::string>{"--kitti", kitti(d), "--imu-csv", d + "/imu.csv", "--out",
                                                     d + "/o.rawlog"};
                 },
                 1, {"imu.csv:3"}});
    c.push_back({"ImportOdomCsvNotUnit", I,
                 [](const std::string& d) {
                     write(d + "/odom.csv", "0.0 0 0 0 0 0 0 1\n0.1 0 0 0 0 0 0 3\n");
                     return std::vector<std::string>{"--kitti", kitti(d), "--odom-csv", d + "/odom.csv", "--out",
                                                     d + "/o.rawlog"};
                 },
                 1, {"odom.csv:2"}});
    c.push_back({"ImportPosesRepeatedTime", I,
                 [](const std::string& d) {
                     write(d + "/p.tum", "0.0 0 0 0 0 0 0 1\n0.1 1 0 0 0 0 0 1\n0.1 2 0 0 0 0 0 1\n");
                     return std::vector<std::string>{"--kitti", kitti(d), "--poses", d + "/p.tum", "--out",
                                                     d + "/o.rawlog"};
                 },
                 1, {"p.tum:3: timestamp 0.1 repeats line 2"}});
    c.push_back({"ImportGarbageBag", I,
                 [](const std::string& d) {
                     write(d + "/run.bag", "#ROSBAG V2.0\ngarbage garbage garbage");
                     return std::vector<std::string>{"--rosbag", d + "/run.bag", "--out", d + "/o.rawlog"};
                 },
                 1, {"run.bag"}});
    c.push_back({"ImportUnwritableOut", I,
                 [](const std::string& d) {
                     return std::vector<std::string>{"--kitti", kitti(d), "--out", d + "/no/such/dir/o.rawlog"};
                 },
                 1, {"o.rawlog"}});
    // ---- superloc-eval (cases 3 and 4) ----
    c.push_back({"EvalNothingMatched", E,
                 [](const std::string& d) {
                     write(d + "/est.tum", "100.0 0 0 0 0 0 0 1\n100.1 1 0 0 0 0 0 1\n");
                     write(d + "/gt.tum", kTum3);
                     return std::vector<std::string>{"--est", d + "/est.tum", "--gt", d + "/gt.tum", "--json", d + "/e.json"};
                 },
                 1, {"no pose of", "est.tum", "assoc_tolerance"}});
    c.push_back({"EvalEmptyEstimate", E,
                 [](const std::string& d) {
                     write(d + "/est.tum", "# t x y z qx qy qz qw\n");
                     write(d + "/gt.tum", kTum3);
                     return std::vector<std::string>{"--est", d + "/est.tum", "--gt", d + "/gt.tum"};
                 },
                 1, {"est.tum: no poses"}});
    c.push_back({"EvalRepeatedTimestamp", E,
                 [](const std::string& d) {
                     write(d + "/est.tum", kTum3);
                     write(d + "/gt.tum", kTum3 + "0.2 3 0 0 0 0 0 1\n");
                     return std::vector<std::string>{"--est", d + "/est.tum", "--gt", d + "/gt.tum"};
                 },
                 1, {"gt.tum:4: timestamp 0.2 repeats line 3"}});
    c.push_back({"EvalSetUnknownSection", E,
                 [](const std::string& d) {
                     write(d + "/est.tum", kTum3);
                     return std::vector<std::string>{"--est", d + "/est.tum", "--gt", d + "/est.tum", "--set", "evl.align=true"};
                 },
                 1, {"--set 'evl.align=true'", "superloc-eval has no section [evl]"}});
    c.push_back({"EvalConfigUnknownSection", E,
                 [](const std::string& d) {
                     write(d + "/est.tum", kTum3);
                     write(d + "/e.ini", "[eval]\nalign = true\n[evaluation]\nassoc_tolerance = 0.5\n");
                     return std::vector<std::string>{"--est", d + "/est.tum", "--gt", d + "/est.tum", "--config", d + "/e.ini"};
                 },
                 1, {"e.ini:3: unknown section [evaluation]"}});
    c.push_back({"EvalTumTooFewNumbers", E,
                 [](const std::string& d) {
                     write(d + "/est.tum", "0.0 0 0 0 0 0 1\n");
                     return std::vector<std::string>{"--est", d + "/est.tum", "--gt", kGt};
                 },
                 1, {"est.tum:1", "expected 8 numbers"}});
    c.push_back({"EvalFramesCsvBroken", E,
                 [](const std::string& d) {
                     write(d + "/est.tum", kTum3);
                     write(d + "/frames.csv", "t,x,y\n0.0,1\n");
                     return std::vector<std::string>{"--est", d + "/est.tum", "--gt", d + "/est.tum", "--frames",
                                                     d + "/frames.csv"};
                 },
                 1, {"frames.csv"}});
    // ---- superloc-sim ----
    c.push_back({"SimSetUnknownSection", S,
                 [](const std::string& d) {
                     return std::vector<std::string>{sourcePath("ini/sim/office.ini"), "--out", d + "/sim", "--set",
                                                     "simm.duration=1"};
                 },
                 1, {"--set 'simm.duration=1'", "superloc-sim has no section [simm]"}});
    c.push_back({"SimDuplicateKey", S,
                 [](const std::string& d) {
                     write(d + "/s.ini", slurp(sourcePath("ini/sim/office.ini")) + "\n[sim]\nduration = 1\n");
                     return std::vector<std::string>{d + "/s.ini", "--out", d + "/sim"};
                 },
                 1, {"s.ini:", "[sim] duration is given twice"}});
    c.push_back({"SimFractionForWholeNumber", S,
                 [](const std::string& d) {
                     return std::vector<std::string>{sourcePath("ini/sim/office.ini"), "--out", d + "/sim", "--set",
                                                     "lidar.columns=450.5"};
                 },
                 1, {"[lidar] columns = '450.5' is not a whole number"}});
    c.push_back({"SimMisspeltSection", S,
                 [](const std::string& d) {
                     write(d + "/s.ini", "[sim]\nworld = office\n[ofice]\nrooms_per_side = 2\n");
                     return std::vector<std::string>{d + "/s.ini", "--out", d + "/sim"};
                 },
                 1, {"s.ini:3: unknown section [ofice]"}});
    const auto sim = [](std::vector<std::string> extra) {
        return [extra](const std::string& d) {
            std::vector<std::string> a = {sourcePath("ini/sim/office.ini"), "--out", d + "/sim"};
            a.insert(a.end(), extra.begin(), extra.end());
            return a;
        };
    };
    c.push_back({"SimUnknownWorld", S, sim({"--set", "sim.world=mars"}), 1, {"office.ini: [sim] world = 'mars' is unknown"}});
    c.push_back({"SimMissingPreset", S, sim({"--set", "lidar.preset=nothere.ini"}), 1,
                 {"[lidar] preset = 'nothere.ini': file not found"}});
    c.push_back({"SimNegativeDuration", S, sim({"--set", "sim.duration=-1"}), 1, {"[sim] duration must be in"}});
    c.push_back({"SimSeedNotANumber", S, sim({"--seed", "abc"}), 1, {"--seed 'abc'"}});
    c.push_back({"SimMissingConfig", S,
                 [](const std::string& d) { return std::vector<std::string>{d + "/none.ini", "--out", d + "/sim"}; }, 1,
                 {"none.ini: cannot open the configuration file"}});
    // ---- superloc-bench (case 7: an unknown method stops the suite before any run) ----
    const auto suite = [](const std::string& d, const std::string& body) {
        write(d + "/suite.ini", "[suite]\nmethods = icp\nsequences = office\nlocalize_config = " + kIni + "\n" + body +
                                    "[seq.office]\ntype = sim\nconfig = " + sourcePath("ini/sim/office.ini") + "\n");
        return d + "/suite.ini";
    };
    c.push_back({"BenchUnknownMethod", B,
                 [suite](const std::string& d) {
                     return std::vector<std::string>{suite(d, ""), "--out", d + "/b", "--methods", "icp icpp"};
                 },
                 1, {"method 'icpp'", "'icpp' is unknown"}});
    c.push_back({"BenchLocalizeSetUnknownSection", B,
                 [suite](const std::string& d) {
                     return std::vector<std::string>{suite(d, ""), "--out", d + "/b", "--localize-set",
                                                     "localisation.method=icp"};
                 },
                 1, {"--localize-set", "no section [localisation]"}});
    c.push_back({"BenchMisspeltSection", B,
                 [suite](const std::string& d) {
                     return std::vector<std::string>{suite(d, "[evl]\nassoc_tolerance = 0.1\n"), "--out", d + "/b"};
                 },
                 1, {"suite.ini:5: unknown section [evl]"}});
    c.push_back({"BenchFractionalSeed", B,
                 [suite](const std::string& d) {
                     std::string path = suite(d, "");
                     std::ofstream(path, std::ios::app) << "seed = 2.5\n";
                     return std::vector<std::string>{path, "--out", d + "/b"};
                 },
                 1, {"suite.ini: [seq.office] seed = '2.5' is not a seed"}});
    c.push_back({"BenchSuiteLocalizeSetBadKey", B,
                 [suite](const std::string& d) {
                     return std::vector<std::string>{suite(d, "localize_set = localization.metod=icp\n"), "--out",
                                                     d + "/b"};
                 },
                 1, {"method 'icp'", "unknown key 'metod'"}});
    // ---- superloc-bench --plan / --run / --collect (doc/evaluation.md#runs-split-for-a-scheduler) ----
    // The suite's plan: data:office (0), office/icp (1), made in d/b by --plan first.
    const auto planned = [suite, B](const std::vector<std::string>& extra) {
        return [suite, B, extra](const std::string& d) {
            const std::string s = suite(d, "");
            const auto p = superloc::app::runProcess({appPath(B), s, "--out", d + "/b", "--plan"}, d + "/plan.log", 120);
            EXPECT_EQ(p.exit_code, 0) << slurp(d + "/plan.log");
            std::vector<std::string> a = {s, "--out", d + "/b"};
            a.insert(a.end(), extra.begin(), extra.end());
            return a;
        };
    };
    const auto unplanned = [suite](const std::vector<std::string>& extra) {
        return [suite, extra](const std::string& d) {
            std::vector<std::string> a = {suite(d, ""), "--out", d + "/b"};
            a.insert(a.end(), extra.begin(), extra.end());
            return a;
        };
    };
    c.push_back({"BenchRunUnknownId", B, planned({"--run", "office/icpp"}), 1,
                 {"--run: 'office/icpp' is not a run of this plan", "index 0-1", "--plan lists them"}});
    c.push_back({"BenchRunIndexOutOfRange", B, planned({"--run", "2"}), 1,
                 {"--run: '2' is not a run of this plan", "index 0-1"}});
    c.push_back({"BenchRunWithoutId", B, planned({"--run"}), 1, {"--run"}});
    c.push_back({"BenchRunWithoutPlan", B, unplanned({"--run", "0"}), 1,
                 {"--run:", "/b/plan.json does not exist: make the plan first", "--plan)"}});
    c.push_back({"BenchRunBeforeItsData", B, planned({"--run", "office/icp"}), 1,
                 {"--run office/icp: its data is not ready", "data:office has not finished",
                  "run data:office (0) first"}});
    c.push_back({"BenchRunOtherMethodsThanPlanned", B, planned({"--run", "0", "--methods", "icp superloc"}), 1,
                 {"--run:", "plan.json plans other runs (2) than this command line (3)", "--methods"}});
    c.push_back({"BenchCollectWithoutPlan", B, unplanned({"--collect"}), 1,
                 {"--collect:", "/b/plan.json does not exist", "--plan)"}});
    c.push_back({"BenchPlanWithJobs", B, unplanned({"--plan", "--jobs", "2"}), 1,
                 {"--jobs: not with --plan", "parallel -j N"}});
    c.push_back({"BenchRunWithJobs", B, unplanned({"--run", "0", "--jobs", "2"}), 1, {"--jobs: not with --run"}});
    c.push_back({"BenchPlanAndCollect", B, unplanned({"--plan", "--collect"}), 1,
                 {"--plan and --collect: give one step at a time"}});
    c.push_back({"BenchRunWithFresh", B, unplanned({"--run", "0", "--fresh"}), 1,
                 {"--fresh: not with --run", "delete DIR/data/SEQ"}});
    c.push_back({"BenchRunWithDropData", B, unplanned({"--run", "1", "--drop-data"}), 1,
                 {"--drop-data: not with --run", "--collect"}});
    return c;
}

class BadInputs : public ::testing::TestWithParam<BadInput> {};

TEST_P(BadInputs, ExitCodeAndOneLineNamingTheCulprit) {
    const BadInput& c = GetParam();
    ASSERT_TRUE(fs::exists(appPath(c.app))) << c.app << " not built";
    const std::string d = superloc::testing::freshDir("bad_input_" + c.name);
    std::vector<std::string> argv = {appPath(c.app)};
    const auto args = c.args(d);
    argv.insert(argv.end(), args.begin(), args.end());
    const superloc::app::ProcessResult p = superloc::app::runProcess(argv, d + "/log.txt", 120);
    const std::string log = slurp(d + "/log.txt");
    ASSERT_TRUE(p.started);
    EXPECT_EQ(p.exit_code, c.exit_code) << log;
    const auto ls = lines(log);
    ASSERT_FALSE(ls.empty()) << "nothing said";
    // The error is the last line, one line with the app's name; a warning is one line too.
    std::string said = ls.back();
    if (c.exit_code == 0)
        for (const auto& l : ls)
            if (l.find("warning") != std::string::npos) said = l;
    EXPECT_EQ(said.rfind(c.app + ": ", 0), 0u) << log;
    for (const auto& e : c.expect) EXPECT_NE(said.find(e), std::string::npos) << "'" << e << "' not in: " << said;
    for (const char* trace : {"====", "Perhaps it's a gz", "Call stack"})
        EXPECT_EQ(log.find(trace), std::string::npos) << log;
}

INSTANTIATE_TEST_SUITE_P(Apps, BadInputs, ::testing::ValuesIn(cases()),
                         [](const ::testing::TestParamInfo<BadInput>& i) { return i.param.name; });

/// Rows of a CSV or TUM file that are not comments or the header.
size_t dataRows(const std::string& path, bool header) {
    size_t n = 0;
    for (const auto& l : lines(slurp(path))) n += l[0] != '#';
    return n - (header && n > 0);
}

// Issue 36, case 2: a rawlog cut inside its 10th scan. The reader holds the newest 0.5 s in its
// re-sort window; the 9 scans before the cut are in it when the read fails, and must be
// localized and written before the run stops.
TEST(BadInput, TruncatedRawlogKeepsEveryFrameBeforeTheCut) {
    const std::string d = superloc::testing::freshDir("bad_input_truncated");
    const PlainRawlog r = plainRawlog();
    ASSERT_EQ(r.scans.size(), 10u);
    const auto [begin, end] = r.scans[9];
    write(d + "/cut.rawlog", r.bytes.substr(0, (begin + end) / 2));
    std::vector<std::string> argv = {appPath("superloc-localize")};
    for (const auto& a : localize(d, "", {}, d + "/cut.rawlog")) argv.push_back(a);
    const auto p = superloc::app::runProcess(argv, d + "/log.txt", 120);
    const std::string log = slurp(d + "/log.txt");
    EXPECT_EQ(p.exit_code, 1) << log;
    ASSERT_FALSE(lines(log).empty());
    EXPECT_NE(lines(log).back().find("cut.rawlog: entry"), std::string::npos) << log;
    EXPECT_EQ(dataRows(d + "/out/trajectory.tum", false), 9u) << log;
    EXPECT_EQ(dataRows(d + "/out/frames.csv", true), 9u) << log;
    const std::string summary = slurp(d + "/out/summary.json");
    EXPECT_NE(summary.find("\"failed\""), std::string::npos) << summary;
    // The same 9 scan times as the clean rawlog's first 9 poses.
    const auto est = superloc::io::loadTum(d + "/out/trajectory.tum");
    const auto gt = superloc::io::loadTum(kGt);
    ASSERT_GE(gt.size(), 9u);
    for (size_t i = 0; i < est.size(); ++i) EXPECT_NEAR(est[i].t, gt[i].t, 1e-6) << i;
}

// Issue 36, case 6: a voxel far below the points' resolution keeps every point (it merged
// distant points when the 32-bit voxel index overflowed).
TEST(BadInput, TinyVoxelMapKeepsEveryPoint) {
    const std::string d = superloc::testing::freshDir("bad_input_tiny_voxel");
    for (const char* v : {"0", "1e-9"}) {
        const auto q = superloc::app::runProcess({appPath("superloc-map"), "--rawlog", kRawlog, "--voxel", v,
                                                  "--no-normals", "--out", d + "/m" + v + ".pcd"},
                                                 d + "/log.txt", 120);
        ASSERT_EQ(q.exit_code, 0) << slurp(d + "/log.txt");
    }
    const auto all = slurp(d + "/m0.pcd"), tiny = slurp(d + "/m1e-9.pcd");
    const auto points = [](const std::string& pcd) {
        const size_t at = pcd.find("\nPOINTS ");
        return std::stoul(pcd.substr(at + 8));
    };
    EXPECT_EQ(points(tiny), points(all));
    // The localizer's map filter ([map] voxel_size) the same: as many map points as with 0.
    std::vector<size_t> map_points;
    for (const char* v : {"0", "1e-9"}) {
        std::vector<std::string> argv = {appPath("superloc-localize")};
        for (const auto& a : localize(d + "/" + v, "", {"--set", std::string("map.voxel_size=") + v}))
            argv.push_back(a);
        const auto p = superloc::app::runProcess(argv, d + "/loc.txt", 120);
        ASSERT_EQ(p.exit_code, 0) << slurp(d + "/loc.txt");
        const auto summary = nlohmann::json::parse(slurp(d + "/" + v + "/out/summary.json"));
        map_points.push_back(summary.at("map_points").get<size_t>());
    }
    EXPECT_EQ(map_points[1], map_points[0]);
    EXPECT_EQ(map_points[0], points(slurp(kMap)));
}

}  // namespace
