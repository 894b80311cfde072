// Stand-ins for the apps superloc-bench runs (shell scripts honouring their command lines), so
// that the suite logic is tested without the real simulator and localizer. Used by
// test_bench_app.cpp and test_bench_plan.cpp.
#pragma once

#include <sys/stat.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace superloc::testing::bench {
namespace fs = std::filesystem;

inline void writeScript(const std::string& path, const std::string& body) {
    std::ofstream(path) << "#!/bin/sh\n" << body;
    ::chmod(path.c_str(), 0755);
}

// Argument parsing shared by the stand-ins: sets OUT, METHOD, GT from the flags; --dump-config
// (superloc-bench's check of each method before the runs) succeeds at once.
inline const char* kParse =
    "while [ $# -gt 0 ]; do case \"$1\" in --out) OUT=$2; shift;; --method) METHOD=$2; shift;;"
    " --initial-pose-tum) GT=$2; shift;; --dump-config) exit 0;; esac; shift; done\n";

// superloc-sim: 11 GT poses 1 m apart along x; GT map = 21 x 3 points on the plane z = 0.
inline const char* kSim =
    "mkdir -p \"$OUT\"; echo raw > \"$OUT/sequence.rawlog\"; echo map > \"$OUT/prior_map.pcd\"\n"
    "i=0; : > \"$OUT/gt_tum.txt\"; while [ $i -le 10 ]; do echo \"$i.0 $i 0 0 0 0 0 1\" >> "
    "\"$OUT/gt_tum.txt\"; i=$((i+1)); done\n"
    "{ printf 'ply\\nformat ascii 1.0\\nelement vertex 63\\nproperty float x\\nproperty float "
    "y\\nproperty float z\\nend_header\\n';\n"
    "  for x in 0 1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16 17 18 19 20; do for y in 0 1 2; do echo "
    "\"$x $y 0\"; done; done; } > \"$OUT/gt_map.ply\"\n";

// superloc-localize: `good` reproduces GT with its map on the plane; `lift` is 0.2 m too high;
// `stop` writes the first 6 poses and fails (exit 3).
inline const char* kLocalize =
    "mkdir -p \"$OUT\"; Z=0; N=11; RC=0\n"
    "[ \"$METHOD\" = lift ] && Z=0.2\n"
    "[ \"$METHOD\" = stop ] && N=6 && RC=3\n"
    "head -n $N \"$GT\" | awk -v z=$Z '{ $4 = $4 + z; print }' > \"$OUT/trajectory.tum\"\n"
    "echo 't,gamma_x,gamma_y,gamma_z,gamma_roll,gamma_pitch,gamma_yaw,degenerate,ms_total' > "
    "\"$OUT/frames.csv\"\n"
    "i=0; while [ $i -lt $N ]; do echo \"$i.0,0.1,1,1,1,1,1,x,$((10+i))\" >> \"$OUT/frames.csv\"; "
    "i=$((i+1)); done\n"
    "{ printf '# .PCD v0.7\\nVERSION 0.7\\nFIELDS x y z\\nSIZE 4 4 4\\nTYPE F F F\\nCOUNT 1 1 "
    "1\\nWIDTH 3\\nHEIGHT 1\\n"
    "VIEWPOINT 0 0 0 1 0 0 0\\nPOINTS 3\\nDATA ascii\\n'; echo \"1 1 $Z\"; echo \"5 1 $Z\"; echo "
    "\"9 2 $Z\"; } > \"$OUT/localized_map.pcd\"\n"
    "exit $RC\n";

// For the --jobs test, before kLocalize: every run marks its start in its sequence's folder;
// when TOOLS/rendezvous exists, `good` waits (up to 20 s) for another run to be going at the
// same time — `lift` of its sequence, or the other sequence's `good` (which is itself waiting)
// — and writes whether it met one (`met`) into good.rendezvous. Waiting for `lift` alone could
// deadlock when both sequences' data are ready together and the two `good` runs take both
// jobs (seen under the sanitizers, where the simulations are slower).
// `hang` never finishes (the suite's timeout kills it).
inline const char* kRendezvous =
    "[ \"$METHOD\" = hang ] && exec sleep 60\n"
    "mkdir -p \"$OUT\"; touch \"$OUT/../$METHOD.started\"\n"
    "if [ \"$METHOD\" = good ] && [ -e \"$(dirname \"$0\")/rendezvous\" ]; then\n"
    "  met() { [ -e \"$OUT/../lift.started\" ] && return 0; set -- \"$OUT\"/../../*/good.started; [ $# -ge 2 ]; }\n"
    "  n=0; while ! met && [ $n -lt 200 ]; do sleep 0.1; n=$((n+1)); done\n"
    "  if met; then echo met; else echo alone; fi > \"$OUT/../good.rendezvous\"\n"
    "fi\n";

/// A suite of two stand-in sequences in `d`, with these methods.
inline std::string writeTwoSequenceSuite(const std::string& d, const std::string& methods, int timeout) {
    const std::string tools = d + "/tools";
    fs::create_directories(tools);
    writeScript(tools + "/superloc-sim", std::string(kParse) + kSim);
    writeScript(tools + "/superloc-localize", std::string(kParse) + kRendezvous + kLocalize);
    std::ofstream(d + "/localize.ini") << "[localization]\n";
    std::ofstream(d + "/world.ini") << "[sim]\n";
    std::ofstream(d + "/suite.ini") << "[suite]\nmethods = " << methods
                                    << "\nsequences = plane hall\nlocalize_config = localize.ini\n"
                                    << "timeout = " << timeout << "\n[seq.plane]\ntype = sim\n"
                                    << "config = world.ini\nseed = 3\n[seq.hall]\ntype = sim\n"
                                    << "config = world.ini\nseed = 4\n";
    return tools;
}
}  // namespace superloc::testing::bench
