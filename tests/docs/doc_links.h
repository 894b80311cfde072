// The documentation's references, checked: relative links of the Markdown pages and every
// `doc/<page>.md#<anchor>` cited anywhere (code comments, INI files, scripts, --help texts).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace superloc::testing::docs {

struct LinkCheck {
    size_t files = 0;       ///< text files read
    size_t references = 0;  ///< links and doc/ references checked
    /// "FILE:LINE: 'target': no such file", "... no heading with anchor #A in PAGE", or a
    /// citation of the founding design guide (not in the repository)
    std::vector<std::string> problems;
};

/// Reads every text file (.md .h .cpp .txt .cmake .ini .sh .py .in) under `root`, skipping
/// hidden folders, build* folders and out/. A link's target must exist (relative to its page);
/// an anchor must be a heading's anchor (headingAnchors) in the .md page it names.
LinkCheck checkLinks(const std::string& root);

}  // namespace superloc::testing::docs
