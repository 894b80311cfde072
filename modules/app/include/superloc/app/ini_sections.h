// The INI sections each app reads (core's checkSections, doc/design.md#9-command-line): MRPT
// ignores a section nobody reads, so a misspelt one ([localisation]) would leave every key of
// it at its default without a word. An INI file may hold the sections of the other apps that
// read INI files of the same kind (one file for superloc-localize, -map, -import and -eval);
// a --set may only name a section the app itself reads.
#pragma once

#include <superloc/core/config.h>

namespace superloc::app {

/// superloc-localize: [run], [rawlog], [map] and the Localizer's sections.
const IniSections& localizeSections();
/// superloc-map --config / --set: [rawlog].
const IniSections& mapSections();
/// superloc-import --config / --set: [rosbag].
const IniSections& importSections();
/// superloc-eval --config / --set: [eval].
const IniSections& evalSections();
/// superloc-bench's suite files: [suite], [eval] and [seq.NAME].
const IniSections& suiteSections();

}  // namespace superloc::app
