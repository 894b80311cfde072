#include "doc_links.h"

#include <algorithm>
#include <filesystem>
#include <map>
#include <regex>
#include <set>
#include <sstream>

#include "doc_blocks.h"

namespace fs = std::filesystem;

namespace superloc::testing::docs {

LinkCheck checkLinks(const std::string& root_dir) {
    static const std::set<std::string> kText = {".md", ".h", ".cpp", ".txt", ".cmake", ".ini", ".sh", ".py", ".in"};
    // Built here so that this file does not cite the guide itself.
    static const std::vector<std::string> kGuide = {std::string("DESIGN") + " \xC2\xA7", std::string("DESIGN") + ".md"};
    static const std::regex kMdLink(R"(\]\(([^)\s]+)\))");
    static const std::regex kDocRef(R"((^|[^A-Za-z0-9_./-])(doc/[A-Za-z0-9_./-]+\.md)#([A-Za-z0-9_-]+))");
    const fs::path root = fs::absolute(root_dir);
    std::map<fs::path, std::set<std::string>> anchors;
    LinkCheck out;
    const auto check = [&](const std::string& where, const fs::path& target, const std::string& anchor,
                           const std::string& as_written) {
        ++out.references;
        if (!fs::exists(target)) {
            out.problems.push_back(where + ": '" + as_written + "': no such file");
            return;
        }
        if (anchor.empty() || target.extension() != ".md") return;
        const fs::path key = fs::canonical(target);
        auto it = anchors.find(key);
        if (it == anchors.end()) it = anchors.emplace(key, headingAnchors(readText(key))).first;
        if (!it->second.count(anchor))
            out.problems.push_back(where + ": '" + as_written + "': no heading with anchor #" + anchor + " in " +
                                   fs::relative(key, fs::canonical(root)).string());
    };
    std::vector<fs::path> files;  // in name order, so that the problems come in a stable order
    for (auto it = fs::recursive_directory_iterator(root); it != fs::recursive_directory_iterator(); ++it) {
        const std::string name = it->path().filename().string();
        if (it->is_directory() && (name[0] == '.' || name.rfind("build", 0) == 0 || name == "out"))
            it.disable_recursion_pending();
        else if (it->is_regular_file() && kText.count(it->path().extension().string()))
            files.push_back(it->path());
    }
    std::sort(files.begin(), files.end());
    for (const auto& file : files) {
        ++out.files;
        const bool md = file.extension() == ".md";
        const std::string rel = fs::relative(file, root).string();
        std::istringstream in(readText(file));
        int n = 0;
        for (std::string line; std::getline(in, line);) {
            const std::string where = rel + ":" + std::to_string(++n);
            for (const auto& g : kGuide)
                if (line.find(g) != std::string::npos)
                    out.problems.push_back(where + ": cites the founding design guide, which is not in the "
                                           "repository: cite a section of doc/design.md or a doc/ page instead");
            for (std::sregex_iterator m(line.begin(), line.end(), kDocRef), e; m != e; ++m)
                check(where, root / (*m)[2].str(), (*m)[3].str(), (*m)[2].str() + "#" + (*m)[3].str());
            if (!md) continue;
            for (std::sregex_iterator m(line.begin(), line.end(), kMdLink), e; m != e; ++m) {
                const std::string t = (*m)[1].str();
                if (t.find("://") != std::string::npos || t.rfind("mailto:", 0) == 0) continue;
                const auto hash = t.find('#');
                const std::string path = t.substr(0, hash);
                const std::string anchor = hash == std::string::npos ? "" : t.substr(hash + 1);
                check(where, path.empty() ? file : file.parent_path() / path, anchor, t);
            }
        }
    }
    return out;
}

}  // namespace superloc::testing::docs
