# CTest Build.NoCpuSpecificFlags: cmake -DCOMMANDS=<build>/compile_commands.json -P this file.
# Fails when any compile command of the build holds a CPU-specific flag (-march=..., -mtune=native,
# -mavx*, -mfma): Debian's MRPT, PCL and Ceres are built for the x86-64 baseline, and Eigen
# objects aligned for AVX in our code but not in theirs crash at run time. Covers what the
# configure-time guard in superloc.cmake cannot see: target options and options exported by
# imported targets (INTERFACE_COMPILE_OPTIONS of a dependency).
if(NOT EXISTS "${COMMANDS}")
  message(FATAL_ERROR "${COMMANDS}: no compile database (CMAKE_EXPORT_COMPILE_COMMANDS)")
endif()
file(READ "${COMMANDS}" db)
string(REGEX MATCHALL "\"command\"" entries "${db}")
list(LENGTH entries n)
if(n EQUAL 0)
  message(FATAL_ERROR "${COMMANDS}: no compile command in it")
endif()
string(REGEX MATCHALL "[ \"]-(march=[^ \"]+|mtune=native|mavx[^ \"]*|mfma)" bad "${db}")
if(bad)
  list(REMOVE_DUPLICATES bad)
  message(FATAL_ERROR "CPU-specific compile flags in ${COMMANDS}: ${bad}")
endif()
message(STATUS "${n} compile commands, no CPU-specific flag")
