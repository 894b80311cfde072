// The documentation kept true by the suite (CONTRIBUTING.md, "Documented commands"):
// - Docs.ReadmeCommandsRun, Docs.YourDataCommandsRun: every ```bash block of README.md and
//   doc/your-data.md runs as written (doc_sandbox.h) unless a marker skips it with a reason,
//   exits 0 within its budget, and every app in it writes the files its command line promises.
// - Docs.LinksAndAnchorsResolve: the pages' relative links, and every `doc/<page>.md#<anchor>` cited
//   in code, INI and scripts, lead to a file and a heading that exist; nothing cites the founding
//   design guide, which is not in the repository.
// - The machinery itself: markers, anchors, a broken command, a missing output, a budget.
#include <superloc_testing/testing.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <set>
#include <sys/wait.h>

#include "doc_blocks.h"
#include "doc_links.h"
#include "doc_sandbox.h"

namespace fs = std::filesystem;
using namespace superloc::testing::docs;

namespace {

/// The last `n` lines of `text` (all of it when it has fewer).
std::string lastLines(const std::string& text, size_t n) {
    size_t start = text.size(), seen = 0;
    if (start > 0 && text[start - 1] == '\n') --start;  // the final line break ends the last line
    while (start > 0 && seen < n)
        if (text[--start] == '\n' && ++seen == n) return text.substr(start + 1);
    return text;
}

DocSandbox sandbox(const std::string& name) {
    return DocSandbox(superloc::testing::freshDir(name), SUPERLOC_SOURCE_DIR, SUPERLOC_BINARY_DIR,
                      superloc::testing::sharedData());
}

/// Runs every block of `page` (a path in the source tree) in one sandbox, in order: later blocks
/// may use an earlier one's files, so the first failure ends the page.
void runPage(const std::string& page) {
    SUPERLOC_REQUIRE_DATA("kitti00-mini");
    const auto blocks = bashBlocks(readText(superloc::testing::sourcePath(page)), page);
    const DocSandbox box = sandbox("docs_page");
    int ran = 0;
    for (const auto& b : blocks) {
        if (b.skip) {
            std::cout << "[ docs ] " << page << ":" << b.line << " skipped (" << b.skip_reason << ")\n";
            continue;
        }
        const BlockRun r = box.run(b);
        ++ran;
        std::cout << "[ docs ] " << page << ":" << b.line << " exit " << r.exit_code << " in " << r.seconds
                  << " s (budget " << b.budget_s << " s)\n";
        if (r.exit_code != 0) {
            ADD_FAILURE() << page << ":" << b.line << ": the ```bash block failed (exit " << r.exit_code
                          << "); the end of its output:\n"
                          << lastLines(r.log, 40);
            return;
        }
    }
    EXPECT_GT(ran, 0) << page << " has no ```bash block that runs";
}

}  // namespace

TEST(Docs, MarkersAreReadAndChecked) {
    const std::string md =
        "# Page\n"
        "```\nnot bash\n```\n"
        "```bash\necho one\n```\n"
        "Text.\n"
        "<!-- docs-test: skip (needs a robot) -->\n"
        "```bash\nrun-robot\n```\n"
        "<!-- docs-test: after make data -->\n"
        "<!-- docs-test: budget 30 -->\n"
        "~~~bash\nls /tmp/x\n~~~\n"
        "```cpp\nint main() {}\n```\n";
    const auto b = bashBlocks(md, "p.md");
    ASSERT_EQ(b.size(), 3u);
    EXPECT_EQ(b[0].line, 5);
    EXPECT_EQ(b[0].text, "echo one\n");
    EXPECT_FALSE(b[0].skip);
    EXPECT_EQ(b[0].budget_s, kDefaultBudget);
    EXPECT_TRUE(b[1].skip);
    EXPECT_EQ(b[1].skip_reason, "needs a robot");
    EXPECT_EQ(b[1].text, "run-robot\n");
    EXPECT_FALSE(b[2].skip);
    EXPECT_EQ(b[2].after, std::vector<std::string>{"make data"});
    EXPECT_EQ(b[2].budget_s, 30);
    EXPECT_EQ(b[2].file, "p.md");

    using superloc::testing::errorOf;
    const auto err = [](const std::string& text) { return errorOf([&] { bashBlocks(text, "p.md"); }); };
    EXPECT_EQ(err("<!-- docs-test: skip -->\n```bash\nx\n```\n"),
              "p.md:1: docs-test marker: 'skip' needs a reason in parentheses: skip (why)");
    EXPECT_EQ(err("a\n<!-- docs-test: skip () -->\n```bash\nx\n```\n"),
              "p.md:2: docs-test marker: 'skip' needs a reason in parentheses: skip (why)");
    EXPECT_EQ(err("<!-- docs-test: skipp (x) -->\n```bash\nx\n```\n"),
              "p.md:1: docs-test marker: unknown directive 'skipp (x)' (known: skip (why), after CMD, budget S)");
    EXPECT_EQ(err("<!-- docs-test: budget 0 -->\n```bash\nx\n```\n"),
              "p.md:1: docs-test marker: 'budget' needs a positive number of seconds, got '0'");
    EXPECT_EQ(err("<!-- docs-test: skip (x) -->\n\n```bash\nx\n```\n"),
              "p.md:1: docs-test marker not followed by a ```bash fence");
    EXPECT_EQ(err("<!-- docs-test: skip (x) -->\n```cpp\nx\n```\n"),
              "p.md:1: docs-test marker before a 'cpp' fence, not a ```bash one");
    EXPECT_EQ(err("x\n<!-- docs-test: skip (x)\n"),
              "p.md:2: docs-test marker must be one line: <!-- docs-test: DIRECTIVE -->");
    EXPECT_EQ(err("```bash\nx\n"), "p.md:1: code fence never closed");
}

TEST(Docs, HeadingAnchorsAsGitHubMakesThem) {
    EXPECT_EQ(headingAnchor("5. Alignment risk and active fusion"), "5-alignment-risk-and-active-fusion");
    EXPECT_EQ(headingAnchor("Prior map (`superloc::map::PriorMap`)"), "prior-map-superlocmappriormap");
    EXPECT_EQ(headingAnchor("A robust loss on the prior (`[fusion] prior_kernel = cauchy`)"),
              "a-robust-loss-on-the-prior-fusion-prior_kernel--cauchy");
    EXPECT_EQ(headingAnchor("The prior weight: the scan's mean information"),
              "the-prior-weight-the-scans-mean-information");
    EXPECT_EQ(headingAnchor("Speed — γ × 2"), "speed--γ--2");
    const auto a = headingAnchors("# A\n## Notes\n```\n# not a heading\n```\n### Notes\n#nospace\n");
    EXPECT_EQ(a, (std::set<std::string>{"a", "notes", "notes-1"}));
}

TEST(Docs, ABrokenCommandFailsItsBlock) {
    const DocSandbox box = sandbox("docs_broken");
    DocBlock b;
    b.file = "page.md";
    b.line = 10;
    b.text = "printf '0 0 0 0 0 0 0 1\\n' > /tmp/gt.tum\n"
             "build/bin/superloc-eval --est /tmp/gt.tum --gt /tmp/gt.tum --jsn /tmp/eval.json\n"
             "echo not reached\n";
    const BlockRun r = box.run(b);
    EXPECT_NE(r.exit_code, 0);
    EXPECT_FALSE(r.over_budget);
    EXPECT_NE(r.log.find("--jsn"), std::string::npos) << r.log;
    EXPECT_NE(r.log.find("docs-test: page.md:12: exit "), std::string::npos) << r.log;
    EXPECT_EQ(r.log.find("not reached"), std::string::npos) << r.log;
    EXPECT_EQ(lastLines("a\nb\nc\n", 2), "b\nc\n");
    EXPECT_EQ(lastLines("a\nb", 5), "a\nb");
    // /tmp/ of the block is the sandbox's: the real /tmp/gt.tum is untouched.
    EXPECT_TRUE(fs::exists(fs::path(box.root()).parent_path() / "tmp/gt.tum"));
}

TEST(Docs, AnAppThatWritesNothingFailsItsCommand) {
    const std::string dir = superloc::testing::freshDir("docs_wrapper");
    const auto wrap = [&](const std::string& name, const std::string& real) {
        const std::string path = dir + "/" + name;
        std::ofstream(path) << appWrapper(name, real);
        return "bash " + path;
    };
    const auto run = [&](const std::string& cmd) {
        const int s = std::system((cmd + " > " + dir + "/out.txt 2>&1").c_str());
        return WIFEXITED(s) ? WEXITSTATUS(s) : -1;
    };
    const std::string eval_ok = wrap("superloc-eval", "/bin/true");
    EXPECT_EQ(run(eval_ok + " --est a --gt b"), 0);  // no --json: nothing promised
    EXPECT_EQ(run(eval_ok + " --est a --gt b --json " + dir + "/e.json"), 3);
    EXPECT_NE(readText(dir + "/out.txt").find("docs-test: superloc-eval exited 0 but did not write " + dir +
                                              "/e.json (--json)"),
              std::string::npos)
        << readText(dir + "/out.txt");
    std::ofstream(dir + "/e.json") << "{}\n";
    EXPECT_EQ(run(eval_ok + " --est a --gt b --json=" + dir + "/e.json"), 0);
    EXPECT_EQ(run(eval_ok + " --help --json " + dir + "/none.json"), 0);
    EXPECT_EQ(run(wrap("superloc-eval", "/bin/false") + " --json " + dir + "/e.json"), 1);
    // The files inside --out: a run folder without frames.csv fails.
    fs::create_directories(dir + "/run");
    std::ofstream(dir + "/run/trajectory.tum") << "0 0 0 0 0 0 0 1\n";
    std::ofstream(dir + "/run/summary.json") << "{}\n";
    EXPECT_EQ(run(wrap("superloc-localize", "/bin/true") + " x.ini --out " + dir + "/run"), 3);
    EXPECT_NE(readText(dir + "/out.txt").find("did not write " + dir + "/run/frames.csv (--out)"),
              std::string::npos);
    // An executable the docs test promises nothing for runs as it is.
    EXPECT_EQ(run(wrap("rawlog-edit", "/bin/false")), 1);
}

TEST(Docs, ABlockOverItsBudgetIsStopped) {
    const DocSandbox box = sandbox("docs_budget");
    DocBlock b;
    b.file = "page.md";
    b.line = 1;
    b.budget_s = 1;
    b.text = "sleep 60\n";
    const BlockRun r = box.run(b);
    EXPECT_TRUE(r.over_budget);
    EXPECT_NE(r.exit_code, 0);
    EXPECT_NE(r.log.find("over its budget of 1 s"), std::string::npos) << r.log;
}

TEST(Docs, ReadmeCommandsRun) { runPage("README.md"); }

TEST(Docs, YourDataCommandsRun) { runPage("doc/your-data.md"); }

TEST(Docs, LinksAndAnchorsResolve) {
    const LinkCheck c = checkLinks(SUPERLOC_SOURCE_DIR);
    std::cout << "[ docs ] " << c.files << " files, " << c.references << " links and references checked\n";
    EXPECT_GT(c.references, 100u);
    std::string all;
    for (const auto& p : c.problems) all += p + "\n";
    EXPECT_TRUE(c.problems.empty()) << c.problems.size() << " broken:\n" << all;
}

TEST(Docs, ABrokenLinkOrAnchorIsFound) {
    const fs::path dir = superloc::testing::freshDir("docs_links");
    fs::create_directories(dir / "doc/notes");
    fs::create_directories(dir / "build");
    // "doc/" + page + "#anchor" is spelled in two pieces so that the check of this repository's
    // own files does not read these fixtures as references.
    const std::string d = std::string("doc") + "/";
    std::ofstream(dir / "doc/a.md") << "# A page\n## Section two: `x::y`\nSee [b](b.md), [two](#section-two-xy),\n"
                                       "[web](https://x.org/#nothing).\n";
    std::ofstream(dir / "doc/b.md") << "# B\nBack to [a](a.md#section-two-xy) and [gone](a.md#section-three).\n"
                                       "[up](../README.md) [note](notes/n.md)\n";
    std::ofstream(dir / "README.md") << "[a](" << d << "a.md#a-page)\n";
    std::ofstream(dir / "code.h") << "// " << d << "a.md#section-two-xy, " << d << "b.md#b, " << d << "a.md#nope, "
                                  << d << "c.md#x\n// as in " << std::string("DESIGN") << " \xC2\xA7" << "5\n";
    std::ofstream(dir / "build/skipped.md") << "[x](nowhere.md)\n";
    const LinkCheck c = checkLinks(dir.string());
    EXPECT_EQ(c.files, 4u);
    EXPECT_EQ(c.references, 12u);
    EXPECT_EQ(c.problems,
              (std::vector<std::string>{
                  "code.h:1: '" + d + "a.md#nope': no heading with anchor #nope in " + d + "a.md",
                  "code.h:1: '" + d + "c.md#x': no such file",
                  "code.h:2: cites the founding design guide, which is not in the repository: cite a section of "
                  "doc/design.md or a doc/ page instead",
                  "doc/b.md:2: 'a.md#section-three': no heading with anchor #section-three in " + d + "a.md",
                  "doc/b.md:3: 'notes/n.md': no such file"}))
        << c.problems.size();
}
