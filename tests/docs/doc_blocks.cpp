#include "doc_blocks.h"

#include <algorithm>
#include <cctype>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

namespace superloc::testing::docs {
namespace {

std::string trim(const std::string& s) {
    const auto b = s.find_first_not_of(" \t\r");
    if (b == std::string::npos) return "";
    const auto e = s.find_last_not_of(" \t\r");
    return s.substr(b, e - b + 1);
}

bool startsWith(const std::string& s, const std::string& p) { return s.compare(0, p.size(), p) == 0; }

std::vector<std::string> lines(const std::string& text) {
    std::vector<std::string> out;
    std::istringstream in(text);
    for (std::string l; std::getline(in, l);) out.push_back(l);
    return out;
}

/// A fence line: up to three spaces, then ``` or ~~~; `info` gets what follows.
bool isFence(const std::string& line, std::string& info) {
    const auto b = line.find_first_not_of(' ');
    if (b == std::string::npos || b > 3) return false;
    const std::string rest = line.substr(b);
    if (!startsWith(rest, "```") && !startsWith(rest, "~~~")) return false;
    const auto after = rest.find_first_not_of(rest[0]);
    info = after == std::string::npos ? "" : trim(rest.substr(after));
    return true;
}

[[noreturn]] void fail(const std::string& file, int line, const std::string& what) {
    throw std::runtime_error(file + ":" + std::to_string(line) + ": " + what);
}

/// Applies one marker's directive to `b`.
void applyMarker(const std::string& directive, const std::string& file, int line, DocBlock& b) {
    const std::string word = directive.substr(0, directive.find_first_of(" \t("));
    if (word == "skip") {
        const std::string rest = trim(directive.substr(4));
        if (rest.size() < 3 || rest.front() != '(' || rest.back() != ')' ||
            trim(rest.substr(1, rest.size() - 2)).empty())
            fail(file, line, "docs-test marker: 'skip' needs a reason in parentheses: skip (why)");
        b.skip = true;
        b.skip_reason = trim(rest.substr(1, rest.size() - 2));
    } else if (word == "after") {
        const std::string cmd = trim(directive.substr(5));
        if (cmd.empty()) fail(file, line, "docs-test marker: 'after' needs a command");
        b.after.push_back(cmd);
    } else if (word == "budget") {
        const std::string v = trim(directive.substr(6));
        const bool digits = !v.empty() && v.size() <= 5 && std::all_of(v.begin(), v.end(), [](char c) {
            return std::isdigit(static_cast<unsigned char>(c));
        });
        if (!digits || std::stoi(v) <= 0)
            fail(file, line, "docs-test marker: 'budget' needs a positive number of seconds, got '" + v + "'");
        b.budget_s = std::stoi(v);
    } else {
        fail(file, line, "docs-test marker: unknown directive '" + directive +
                             "' (known: skip (why), after CMD, budget S)");
    }
}

}  // namespace

std::string readText(const std::string& path) {
    std::ifstream in(path);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

std::vector<DocBlock> bashBlocks(const std::string& markdown, const std::string& file) {
    static const std::string kOpen = "<!-- docs-test:", kClose = "-->";
    std::vector<DocBlock> blocks;
    DocBlock pending;
    int pending_line = 0;  // line of the first marker waiting for its fence, 0 = none
    const auto ls = lines(markdown);
    for (size_t i = 0; i < ls.size(); ++i) {
        const int n = static_cast<int>(i) + 1;
        const std::string t = trim(ls[i]);
        std::string info;
        if (startsWith(t, kOpen)) {
            const size_t body = t.size() - kOpen.size();
            if (body < kClose.size() || t.compare(t.size() - kClose.size(), kClose.size(), kClose) != 0)
                fail(file, n, "docs-test marker must be one line: <!-- docs-test: DIRECTIVE -->");
            if (pending_line == 0) {
                pending = DocBlock{};
                pending_line = n;
            }
            applyMarker(trim(t.substr(kOpen.size(), body - kClose.size())), file, n, pending);
            continue;
        }
        if (!isFence(ls[i], info)) {
            if (pending_line != 0) fail(file, pending_line, "docs-test marker not followed by a ```bash fence");
            continue;
        }
        // A fence: find its end (a fence of the same character, no info string).
        size_t end = i + 1;
        std::string close_info;
        while (end < ls.size() && !(isFence(ls[end], close_info) && close_info.empty() &&
                                    trim(ls[end])[0] == trim(ls[i])[0]))
            ++end;
        if (end >= ls.size()) fail(file, n, "code fence never closed");
        const std::string lang = info.substr(0, info.find_first_of(" \t{"));
        if (lang == "bash") {
            DocBlock b = pending_line != 0 ? pending : DocBlock{};
            b.file = file;
            b.line = n;
            for (size_t k = i + 1; k < end; ++k) b.text += ls[k] + "\n";
            blocks.push_back(std::move(b));
        } else if (pending_line != 0) {
            fail(file, pending_line, "docs-test marker before a '" + lang + "' fence, not a ```bash one");
        }
        pending_line = 0;
        i = end;
    }
    if (pending_line != 0) fail(file, pending_line, "docs-test marker not followed by a ```bash fence");
    return blocks;
}

std::string headingAnchor(const std::string& heading) {
    // Non-ASCII punctuation and symbols SuperLoc's pages use in headings (GitHub drops them as
    // it drops ASCII punctuation); other non-ASCII characters (γ, é, ²) are kept.
    static const std::set<std::u32string::value_type> kDropped = {
        0xA7, 0xB0, 0xB1, 0xB7, 0xD7, 0x2013, 0x2014, 0x2018, 0x2019, 0x201C, 0x201D,
        0x2026, 0x2190, 0x2192, 0x2194, 0x2248, 0x2264, 0x2265, 0x207B, 0x2212};
    std::string out;
    for (size_t i = 0; i < heading.size();) {
        const unsigned char c = static_cast<unsigned char>(heading[i]);
        if (c < 0x80) {
            if (std::isalnum(c) || c == '-' || c == '_') out += static_cast<char>(std::tolower(c));
            else if (c == ' ') out += '-';
            ++i;
            continue;
        }
        const size_t len = c >= 0xF0 ? 4 : c >= 0xE0 ? 3 : 2;
        char32_t cp = c & (len == 2 ? 0x1F : len == 3 ? 0x0F : 0x07);
        for (size_t k = 1; k < len && i + k < heading.size(); ++k)
            cp = (cp << 6) | (static_cast<unsigned char>(heading[i + k]) & 0x3F);
        if (!kDropped.count(cp)) out += heading.substr(i, len);
        i += len;
    }
    return out;
}

std::set<std::string> headingAnchors(const std::string& markdown) {
    std::set<std::string> anchors;
    std::string fence_char;
    for (const auto& l : lines(markdown)) {
        std::string info;
        if (isFence(l, info)) {
            const std::string c = trim(l).substr(0, 1);
            if (fence_char.empty()) fence_char = c;
            else if (c == fence_char && info.empty()) fence_char.clear();
            continue;
        }
        if (!fence_char.empty() || !startsWith(l, "#")) continue;
        const auto hashes = l.find_first_not_of('#');
        if (hashes == std::string::npos || hashes > 6 || l[hashes] != ' ') continue;
        const std::string base = headingAnchor(trim(l.substr(hashes)));
        std::string a = base;
        for (int k = 1; anchors.count(a); ++k) a = base + "-" + std::to_string(k);
        anchors.insert(a);
    }
    return anchors;
}

}  // namespace superloc::testing::docs
