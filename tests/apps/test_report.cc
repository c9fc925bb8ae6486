// `grainlift report DIR` through the real command on the tiny DEM case of test_end_to_end: the
// page is written, every image it names is beside it, its table holds the DEM drag of
// summary.json; a folder without results or with a single quote in its name is bad input (exit
// 2), a script that fails is a failed run (exit 1). With /usr/bin/chromium, a headless browser
// loads the page and finds every image element.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <regex>
#include <string>
#include <vector>

#include "run_command.h"
#include "tiny_dem_case.h"

namespace fs = std::filesystem;
using grainlift::test_support::run_command;
using grainlift::test_support::run_grainlift;
using grainlift::test_support::tiny_case;

namespace {


std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

fs::path scratch() {
  fs::path d = fs::temp_directory_path() / ("grainlift_report_" + std::to_string(::getpid()));
  fs::create_directories(d);
  return d;
}

/// The folder of one tiny DEM run with its report, made once for the tests below.
const fs::path& reported_run() {
  static const fs::path dir = [] {
    const fs::path d = scratch();
    std::ofstream(d / "tiny.toml") << tiny_case;
    const auto r = run_grainlift("run " + (d / "tiny.toml").string() +
                                 " --solver dem --quiet --out " + (d / "run").string());
    EXPECT_EQ(r.code, 0) << r.output;
    const auto rep = run_grainlift("report " + (d / "run").string());
    EXPECT_EQ(rep.code, 0) << rep.output;
    EXPECT_NE(rep.output.find((d / "run" / "report.html").string()), std::string::npos)
        << rep.output;
    return d / "run";
  }();
  return dir;
}

std::vector<std::string> img_sources(const std::string& html) {
  std::vector<std::string> out;
  const std::regex img(R"(<img\b[^>]*\bsrc="([^"]*)\")", std::regex::icase);
  for (auto it = std::sregex_iterator(html.begin(), html.end(), img); it != std::sregex_iterator();
       ++it)
    out.push_back((*it)[1].str());
  return out;
}

/// The DEM's "drag" number in summary.json, as written there.
double summary_dem_drag(const std::string& json) {
  const std::size_t dem = json.find("\"dem\"");
  const std::size_t key = json.find("\"drag\":", dem);
  if (dem == std::string::npos || key == std::string::npos) return std::nan("");
  return std::stod(json.substr(key + 7));
}

}  // namespace

TEST(Report, PageNamesOnlyImagesBesideItAndHoldsTheDemDrag) {
  const fs::path& d = reported_run();
  ASSERT_TRUE(fs::exists(d / "report.html"));
  const std::string html = slurp(d / "report.html");
  const std::vector<std::string> srcs = img_sources(html);
  // surface stresses, their split and the fields of the DEM run
  EXPECT_EQ(srcs.size(), 3u) << html;
  for (const auto& s : srcs) {
    EXPECT_EQ(s.find('/'), std::string::npos) << s << ": a relative name beside the page";
    EXPECT_TRUE(fs::exists(d / s)) << s;
  }
  EXPECT_EQ(html.find("http://"), std::string::npos);
  EXPECT_EQ(html.find("https://"), std::string::npos);
  EXPECT_EQ(html.find("<script"), std::string::npos);
  // the table shows the drag of summary.json to 6 significant digits (as %.6g)
  const double drag = summary_dem_drag(slurp(d / "summary.json"));
  ASSERT_TRUE(std::isfinite(drag));
  char shown[32];
  std::snprintf(shown, sizeof shown, "%.6g", drag);
  EXPECT_NE(html.find(std::string("<td>") + shown + " ± "), std::string::npos)
      << shown << " not in\n" << html;
  // the FEM did not run: its column says so
  EXPECT_NE(html.find("not run"), std::string::npos);
}

TEST(Report, FolderWithoutResultsOrWithAQuoteIsBadInput) {
  const fs::path d = scratch() / "empty";
  fs::create_directories(d);
  auto r = run_grainlift("report " + d.string());
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find(d.string()), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("neither dem.h5 nor fem.h5"), std::string::npos) << r.output;

  const fs::path q = scratch() / "it's";
  fs::create_directories(q);
  fs::copy_file(reported_run() / "dem.h5", q / "dem.h5", fs::copy_options::overwrite_existing);
  r = run_grainlift("report \"" + q.string() + "\"");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("single quote"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(q / "report.html"));
}

TEST(Report, ScriptFailureIsAFailedRun) {
  const fs::path d = scratch() / "junk";
  fs::create_directories(d);
  std::ofstream(d / "dem.h5") << "not an HDF5 file\n";
  const auto r = run_grainlift("report " + d.string());
  EXPECT_EQ(r.code, 1) << r.output;
  EXPECT_NE(r.output.find("report.py failed"), std::string::npos) << r.output;
}

// A browser loads the page from the file alone (no network: the page names no address) and
// builds one <img> element per image of the file.
TEST(Report, HeadlessChromiumLoadsThePage) {
  const char* chromium = "/usr/bin/chromium";
  if (!fs::exists(chromium)) GTEST_SKIP() << "browser check skipped: " << chromium << " is absent";
  const fs::path& d = reported_run();
  const fs::path profile = scratch() / "chromium-profile";
  fs::remove_all(profile);
  fs::create_directories(profile);
  const auto r = run_command(std::string(chromium) +
                             " --headless --no-sandbox --disable-gpu"
                             " --disable-background-networking"
                             " --disable-component-update --disable-sync --no-first-run"
                             " --user-data-dir=" + profile.string() + " --dump-dom file://" +
                             (d / "report.html").string());
  EXPECT_EQ(r.code, 0) << r.output;
  const std::string html = slurp(d / "report.html");
  const std::regex img(R"(<img\b)", std::regex::icase);
  const auto count = [&](const std::string& s) {
    return std::distance(std::sregex_iterator(s.begin(), s.end(), img), std::sregex_iterator());
  };
  EXPECT_EQ(count(r.output), count(html)) << r.output;
  EXPECT_NE(r.output.find("</html>"), std::string::npos) << r.output;
}

// `cmake --install BUILD --prefix DIR` gives a DIR/bin/grainlift whose `report` runs the script
// installed in DIR/share/grainlift, not the source tree's: a sentinel report.py put there must
// be the one that runs; then the real one, restored, writes report.html from the installed tree.
// Its continuum runs with the module installed in DIR/lib/grainlift (the loader's log names that
// file), not the build tree's.
TEST(Install, ReportRunsFromThePrefix) {
  const fs::path build = fs::path(GRAINLIFT_BINARY).parent_path().parent_path();
  const fs::path prefix = scratch() / "prefix";
  const auto inst = run_command("cmake --install '" + build.string() +
                                              "' --prefix '" + prefix.string() + "'");
  ASSERT_EQ(inst.code, 0) << inst.output;
  const fs::path g = prefix / "bin" / "grainlift", share = prefix / "share" / "grainlift";
  for (const char* f : {"report.py", "plot_results.py", "plot_rheology.py"})
    EXPECT_TRUE(fs::is_regular_file(share / f)) << f << " not installed";
  // a copy of the build-tree binary's results (the other tests read the original)
  const fs::path run = scratch() / "install_run";
  fs::remove_all(run);
  fs::copy(reported_run(), run, fs::copy_options::recursive);
  const std::string real = slurp(share / "report.py");
  std::ofstream(share / "report.py")
      << "import sys\nopen(sys.argv[1] + '/installed_script_ran', 'w').write('yes')\n";
  run_command("'" + g.string() + "' report '" + run.string() + "'");
  EXPECT_TRUE(fs::exists(run / "installed_script_ran"))
      << "the installed grainlift did not run PREFIX/share/grainlift/report.py";
  std::ofstream(share / "report.py") << real;
  fs::remove(run / "report.html");
  const auto rep = run_command("'" + g.string() + "' report '" + run.string() + "'");
  EXPECT_EQ(rep.code, 0) << rep.output;
  EXPECT_GT(fs::file_size(run / "report.html"), 0u);

  const fs::path module = prefix / "lib" / "grainlift" / "grainlift_fem.so";
  ASSERT_TRUE(fs::is_regular_file(module)) << module << " not installed";
  const auto fem = run_command("LD_DEBUG=files '" + g.string() + "' run '" +
                               std::string(GRAINLIFT_SOURCE_DIR) +
                               "/cases/demo/demo.toml' --solver fem --quiet --set "
                               "continuum.target_error=0 --set continuum.refinement=0 --out '" +
                               (scratch() / "install_fem").string() + "'");
  EXPECT_EQ(fem.code, 0) << fem.output.substr(0, 2000);
  EXPECT_NE(fem.output.find("file=" + module.string()), std::string::npos)
      << "the installed grainlift did not load " << module;
}
