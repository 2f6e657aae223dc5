// `rayaccel bench --report DIR`: the page opens in headless Chromium with every image loaded and no script or
// console error, and names nothing on the network. Skipped where chromium is missing, a failure then under
// RAYACCEL_REQUIRE_CHROMIUM=1 or RAYACCEL_REQUIRE_SHARED=1 (a complete CI machine, see .ci/run).
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>
#include <vector>

#include "cli_runner.h"

namespace rayaccel {
namespace {

using testing::fresh_directory;
using testing::read_file;
using testing::run_cli;

/// Chromium on PATH (Debian's package installs /usr/bin/chromium), else empty.
std::string find_chromium() {
  const char* path = std::getenv("PATH");
  std::string dirs = path ? path : "/usr/bin";
  for (std::size_t start = 0; start <= dirs.size();) {
    const std::size_t end = std::min(dirs.find(':', start), dirs.size());
    for (const char* name : {"chromium", "chromium-browser"}) {
      const std::filesystem::path candidate = std::filesystem::path(dirs.substr(start, end - start)) / name;
      std::error_code ec;
      if (std::filesystem::is_regular_file(candidate, ec)) return candidate.string();
    }
    start = end + 1;
  }
  return {};
}

bool chromium_required() {
  for (const char* name : {"RAYACCEL_REQUIRE_CHROMIUM", "RAYACCEL_REQUIRE_SHARED"}) {
    const char* value = std::getenv(name);
    if (value && std::string(value) == "1") return true;
  }
  return false;
}

/// Runs first in the page: records script errors, failed loads (error events, caught while capturing) and console
/// errors and warnings; after the load event, appends <pre id="probe"> with the images, the broken ones and those.
constexpr const char* kProbe =
    "<script>window.__problems=[];window.addEventListener('error',e=>{__problems.push('error: '+(e.message||"
    "(e.target&&(e.target.src||e.target.href))||'?'))},true);for(const level of ['error','warn']){const f="
    "console[level];console[level]=(...a)=>{__problems.push(level+': '+a.join(' '));f.apply(console,a)}}"
    "window.addEventListener('load',()=>{const bad=[...document.images].filter(i=>!i.complete||i.naturalWidth"
    "===0).map(i=>i.getAttribute('src'));const p=document.createElement('pre');p.id='probe';p.textContent="
    "'images='+document.images.length+' broken='+bad.length+' ['+bad.join(' ')+'] problems=['+__problems.join("
    "' | ')+']';document.body.appendChild(p)});</script>";

TEST(CliBenchReport, PageShowsEveryImageOfflineWithoutErrors) {
  const auto dir = fresh_directory("report");
  const auto report = dir / "report";
  std::vector<std::string> args = {"bench", "builtin:sphere:level=2", "--accel", "bvh_wide,grid", "--res", "16",
                                   "--rays", "primary,shadow", "--repeat", "1", "--report", report.string()};
#ifdef RAYACCEL_HAVE_EMBREE
  args.insert(args.end(), {"--compare", "embree"});
#endif
  const auto result = run_cli(args);
  ASSERT_EQ(result.exit_code, 0) << result.err;
  ASSERT_TRUE(std::filesystem::exists(report / "bench.json"));
  const std::string page = read_file(report / "index.html");
  // Two images (normals, heat map) per rayaccel structure, files beside the page; charts inline; nothing remote.
  const std::regex image("<img src=\"([^\"]+)\"");
  std::size_t images = 0;
  for (auto it = std::sregex_iterator(page.begin(), page.end(), image); it != std::sregex_iterator(); ++it) {
    ++images;
    EXPECT_TRUE(std::filesystem::is_regular_file(report / (*it)[1].str())) << (*it)[1].str();
  }
  EXPECT_EQ(images, 4u) << page;
  EXPECT_EQ(page.find("http:"), std::string::npos);
  EXPECT_EQ(page.find("https:"), std::string::npos);
  EXPECT_EQ(page.find("=\"//"), std::string::npos);
  EXPECT_NE(page.find("<svg"), std::string::npos);
  EXPECT_NE(page.find("<table"), std::string::npos);
  EXPECT_NE(page.find("Machine: "), std::string::npos);
  EXPECT_NE(page.find(", commit "), std::string::npos);

  const std::string chromium = find_chromium();
  if (chromium.empty()) {
    if (chromium_required()) FAIL() << "chromium not found on PATH (scripts/setup.sh installs it)";
    GTEST_SKIP() << "chromium not found on PATH: the page was not opened in a browser (scripts/setup.sh installs "
                    "it; RAYACCEL_REQUIRE_CHROMIUM=1 makes this a failure)";
  }
  // The probe goes first in <head>, in a copy beside the page (same relative image paths).
  std::string probed = page;
  const std::size_t head = probed.find("<head>");
  ASSERT_NE(head, std::string::npos);
  probed.insert(head + 6, kProbe);
  const auto check = report / "check.html";
  std::ofstream(check) << probed;
  const auto browser = testing::run_program(
      "timeout", {"60", chromium, "--headless", "--disable-gpu", "--no-sandbox", "--no-first-run",
                  "--user-data-dir=" + (dir / "chromium-profile").string(), "--enable-logging=stderr", "--v=0",
                  "--dump-dom", "file://" + std::filesystem::absolute(check).string()});
  ASSERT_EQ(browser.exit_code, 0) << browser.err;
  std::smatch probe;
  ASSERT_TRUE(std::regex_search(browser.out, probe, std::regex("<pre id=\"probe\">([^<]*)</pre>")))
      << "the page did not finish loading:\n" << browser.out.substr(0, 2000) << "\n" << browser.err;
  EXPECT_EQ(probe[1].str(), "images=4 broken=0 [] problems=[]");
  EXPECT_EQ(browser.err.find("CONSOLE"), std::string::npos) << browser.err;
}

}  // namespace
}  // namespace rayaccel
