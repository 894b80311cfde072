// What the docs test reads from a Markdown page: its fenced ```bash blocks with the docs-test
// markers in front of them, and its headings' anchors as GitHub makes them.
//
// A ```bash block is run unless a marker says otherwise. Markers are HTML comments on the lines
// right above the fence (GitHub does not render them), one directive each:
//   <!-- docs-test: skip (REASON) -->     not run; the reason is required
//   <!-- docs-test: after COMMAND -->     COMMAND runs first, from the repository root
//   <!-- docs-test: budget SECONDS -->    time budget of the block (default kDefaultBudget)
// A marker that is malformed or not followed by a ```bash fence is an error naming FILE:LINE.
#pragma once

#include <set>
#include <string>
#include <vector>

namespace superloc::testing::docs {

/// The whole text of the file at `path` ("" when it cannot be read).
std::string readText(const std::string& path);

/// [s] a block's time budget when no `budget` marker gives one.
inline constexpr int kDefaultBudget = 180;

struct DocBlock {
    std::string file;   ///< the page, as messages name it (e.g. "README.md")
    int line = 0;       ///< 1-based line of the opening fence
    std::string text;   ///< the lines between the fences, each ending in '\n'
    bool skip = false;
    std::string skip_reason;
    std::vector<std::string> after;  ///< commands run before the block
    int budget_s = kDefaultBudget;
};

/// Every ```bash block of `markdown` (the page `file`), in order. Throws std::runtime_error
/// naming FILE:LINE for a malformed marker, a marker without a ```bash fence after it, or a
/// fence that is never closed.
std::vector<DocBlock> bashBlocks(const std::string& markdown, const std::string& file);

/// The anchor GitHub gives a heading's text: lower case, punctuation and symbols dropped, spaces
/// to '-' (letters, digits, '-', '_' and non-ASCII letters kept).
std::string headingAnchor(const std::string& heading);

/// The anchors of every ATX heading (`# ...` to `###### ...`) outside code fences, a repeated
/// one with GitHub's "-1", "-2", ... suffixes.
std::set<std::string> headingAnchors(const std::string& markdown);

}  // namespace superloc::testing::docs
