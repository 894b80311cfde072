#!/usr/bin/env bash
# Installs SuperLoc's build and run dependencies from Debian 12 packages.
set -euo pipefail
PKGS=(cmake ninja-build g++ pkg-config
      libmrpt-dev mrpt-apps libceres-dev libpcl-dev libeigen3-dev
      libgtest-dev libgmock-dev libbenchmark-dev libembree-dev libtbb-dev
      nlohmann-json3-dev libcli11-dev python3
      # ROS 1 bags (superloc-import --rosbag): rosbag_storage and the message headers
      librosbag-storage-dev pluginlib-dev libsensor-msgs-dev libnav-msgs-dev
      libgeometry-msgs-dev libtf2-msgs-dev
      # ROS 2 bags (.db3: SQLite; .mcap: zstd / lz4 chunks, CRC-32 from zlib)
      libsqlite3-dev libzstd-dev liblz4-dev zlib1g-dev
      # the browser test of report.html (tests/e2e/test_report_browser.cpp: headless Chromium)
      chromium
      # superloc-bench --plan run by GNU parallel (tests BenchPlan.*, BenchQuick.PlanThrough*;
      # doc/evaluation.md#runs-split-for-a-scheduler)
      parallel)
SUDO=""
if [ "$(id -u)" != 0 ]; then SUDO="sudo"; fi
missing=()
for p in "${PKGS[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "installing: ${missing[*]}"
  $SUDO apt-get update
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y --no-install-recommends "${missing[@]}"
fi
