// SPDX-License-Identifier: MIT
// om_dthex when the environment fails: unwritable or absurd output paths (refused before
// any work), a full disk (simulated by a file-size limit), Ctrl-C mid-run and mid-write,
// a time limit. Each must give a clear message, a non-zero exit and leave no partial,
// stale or temporary file.
#include <dthex/io/atomic_file.h>
#include <dthex/io/read_surface.h>
#include <dthex/tets/tetrahedralize.h>
#include "hostile_test_util.h"
#include "bundled_meshes.h"

#include <gtest/gtest.h>

#include <chrono>
#include <csignal>
#include <spawn.h>
#include <thread>
#include <sys/prctl.h>

using namespace dthex_test;

extern char** environ;

namespace {


//! A small valid input that meshes in well under a second.
fs::path write_cube(const fs::path& dir) {
  const fs::path p = dir / "cube.off";
  write_bytes(p, off_text(cube()));
  return p;
}

TEST(FailurePaths, OutputIsADirectoryIsRefusedUpFront) {
  const fs::path dir = fresh_dir("fp_isdir");
  const fs::path input = write_cube(dir);
  fs::create_directory(dir / "o.vtu");
  const CommandRun r = run_om_dthex(input.string() + " -q -o " + (dir / "o.vtu").string(), dir);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("o.vtu"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("is a directory"), std::string::npos) << r.err;
  EXPECT_TRUE(fs::is_directory(dir / "o.vtu"));
  EXPECT_EQ(entries_in(dir / "o.vtu"), 0u);
  fs::remove_all(dir);
}

TEST(FailurePaths, CoarseSurfaceOverTheInputIsRefused) {
  const fs::path dir = fresh_dir("fp_overwrite");
  const fs::path input = write_cube(dir);
  const std::string before = read_bytes(input);
  const CommandRun r = run_om_dthex(input.string() + " -q -o " + (dir / "o.vtu").string() + " --coarse-surface " +
                                        (dir / "." / "cube.off").string(),
                                    dir);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("is the input file"), std::string::npos) << r.err;
  EXPECT_EQ(read_bytes(input), before);
  EXPECT_EQ(entries_in(dir), 1u);
  fs::remove_all(dir);
}

TEST(FailurePaths, ReportInMissingFolderWritesNoMesh) {
  const fs::path dir = fresh_dir("fp_missing");
  const fs::path input = write_cube(dir);
  const CommandRun r = run_om_dthex(input.string() + " -q -o " + (dir / "o.vtu").string() + " --report " +
                                 (dir / "nowhere" / "r.json").string(),
                             dir);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--report"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("does not exist"), std::string::npos) << r.err;
  EXPECT_EQ(entries_in(dir), 1u);  // only the input
  fs::remove_all(dir);
}

TEST(FailurePaths, UnwritableFolderIsExit2BeforeAnyWork) {
  const fs::path dir = fresh_dir("fp_unwritable");
  fs::permissions(dir, fs::perms::owner_all | fs::perms::group_read | fs::perms::group_exec |
                           fs::perms::others_read | fs::perms::others_exec);
  const fs::path input = write_cube(dir);
  const fs::path locked = dir / "locked";
  fs::create_directory(locked);
  fs::permissions(locked, fs::perms::owner_read | fs::perms::owner_exec | fs::perms::group_read |
                              fs::perms::group_exec | fs::perms::others_read | fs::perms::others_exec);
  // root may write anywhere: run the command as nobody then.
  const std::string as_user = ::geteuid() == 0 ? "setpriv --reuid=65534 --regid=65534 --clear-groups " : "";
  // The femur takes many seconds to mesh; the refusal must come first (-v would list stages).
  const CommandRun r = run_om_dthex(dthex_test::bundled_mesh("femur_proximal_ct.off") + " -v -o " + (locked / "o.vtu").string(), dir, as_user);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("not writable"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("read"), std::string::npos) << "no stage may run before the refusal: " << r.err;
  EXPECT_EQ(entries_in(locked), 0u);
  fs::remove_all(dir);
}

TEST(FailurePaths, FullDiskIsExit2WithNoPartialOrTemporaryFile) {
  // ulimit -f 2: files may not grow past 2 KB, so the mesh write fails with EFBIG, as on
  // a full disk. SIGXFSZ must not kill the process: the error is reported.
  const fs::path dir = fresh_dir("fp_full");
  const fs::path input = write_cube(dir);
  const fs::path out = dir / "out";
  fs::create_directory(out);
  const CommandRun r = run_om_dthex(input.string() + " -q -o " + (out / "o.vtu").string(), dir, "ulimit -f 2; ");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("o.vtu"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("File too large"), std::string::npos) << r.err;
  EXPECT_EQ(entries_in(out), 0u) << "partial or temporary file left";
  fs::remove_all(dir);
}

TEST(FailurePaths, FailingReportRemovesTheAlreadyWrittenMesh) {
  // The mesh (THex of the cube, Gmsh format) fits under the size limit, the report does
  // not: since all outputs are committed together, neither may remain. Sizes are measured
  // first, so the limit lies between them whatever the formats' exact sizes.
  const fs::path dir = fresh_dir("fp_report");
  const fs::path input = write_cube(dir);
  const fs::path out = dir / "out";
  fs::create_directory(out);
  const std::string args = input.string() + " -q --thex-only -o " + (out / "o.msh").string() + " --report " +
                           (out / "r.json").string();
  const CommandRun ok = run_om_dthex(args, dir);
  ASSERT_EQ(ok.exit_code, 0) << ok.err;
  const auto mesh_size = fs::file_size(out / "o.msh"), report_size = fs::file_size(out / "r.json");
  fs::remove(out / "o.msh");
  fs::remove(out / "r.json");
  const size_t limit_kb = (mesh_size + 1023) / 1024;  // ulimit -f counts 1024-byte blocks
  if (report_size <= limit_kb * 1024) GTEST_SKIP() << "mesh " << mesh_size << " B, report " << report_size << " B";
  const CommandRun r = run_om_dthex(args, dir, "ulimit -f " + std::to_string(limit_kb) + "; ");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("r.json"), std::string::npos) << r.err;
  EXPECT_EQ(entries_in(out), 0u) << "the mesh was left although the report failed";
  fs::remove_all(dir);
}

TEST(FailurePaths, SigintMidRunExits130AndLeavesNothing) {
  const fs::path dir = fresh_dir("fp_sigint");
  const std::string binary = std::string(DTHEX_BINARY_DIR) + "/om_dthex";
  const std::string input = dthex_test::bundled_mesh("femur_proximal_ct.off"), output = (dir / "o.vtu").string();
  std::vector<std::string> args = {binary, input, "-q", "-o", output, "--report", (dir / "r.json").string()};
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t pid = 0;
  ASSERT_EQ(::posix_spawn(&pid, binary.c_str(), nullptr, nullptr, argv.data(), environ), 0);
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));  // well inside the meshing
  ::kill(pid, SIGINT);
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 130);
  EXPECT_EQ(entries_in(dir), 0u);
  fs::remove_all(dir);
}

TEST(FailurePaths, SigintDuringWritingRemovesTheTemporary) {
  // Deterministic: the writer itself raises SIGINT after writing half a file.
  const fs::path dir = fresh_dir("fp_sigint_write");
  std::fflush(nullptr);
  const pid_t pid = ::fork();
  if (pid == 0) {
    dthex::install_interrupt_cleanup();
    dthex::write_atomically((dir / "o.vtu").string(), [](const std::string& temporary) {
      write_bytes(temporary, std::string(1000, 'x'));
      std::raise(SIGINT);
    });
    ::_exit(0);  // not reached: the handler exits with 130
  }
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 130);
  EXPECT_EQ(entries_in(dir), 0u) << "the temporary file survived the interrupt";
  fs::remove_all(dir);
}

TEST(FailurePaths, WriteGroupCommitsAllOrNothing) {
  const fs::path dir = fresh_dir("fp_group");
  {
    dthex::AtomicWriteGroup group;
    dthex::write_atomically((dir / "a.txt").string(), [](const std::string& t) { write_bytes(t, "a"); });
    EXPECT_FALSE(fs::exists(dir / "a.txt"));  // deferred until commit
    EXPECT_THROW(dthex::write_atomically((dir / "b.txt").string(),
                                         [](const std::string&) { throw std::runtime_error("disk full"); }),
                 dthex::OutputError);
  }  // no commit: a.txt's temporary is removed
  EXPECT_EQ(entries_in(dir), 0u);
  {
    dthex::AtomicWriteGroup group;
    dthex::write_atomically((dir / "a.txt").string(), [](const std::string& t) { write_bytes(t, "a"); });
    dthex::write_atomically((dir / "b.txt").string(), [](const std::string& t) { write_bytes(t, "bb"); });
    group.commit();
  }
  EXPECT_EQ(read_bytes(dir / "a.txt"), "a");
  EXPECT_EQ(read_bytes(dir / "b.txt"), "bb");
  EXPECT_EQ(entries_in(dir), 2u);
  fs::remove_all(dir);
}

TEST(FailurePaths, TetgenTimeLimitIsExit3WithAMessage) {
  const fs::path dir = fresh_dir("fp_time");
  const CommandRun r = run_om_dthex(dthex_test::bundled_mesh("femur_proximal_ct.off") + " -q --thex-only --time-limit 0.01 -o " +
                                 (dir / "o.vtu").string(),
                             dir);
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_NE(r.err.find("time limit"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("femur_proximal_ct.off"), std::string::npos) << r.err;
  EXPECT_EQ(entries_in(dir), 0u);
  fs::remove_all(dir);
}

//! The first child of pid (from /proc/<pid>/task/<pid>/children), or 0.
pid_t first_child(pid_t pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/task/" + std::to_string(pid) + "/children");
  pid_t child = 0;
  in >> child;
  return child;
}

//! True while pid exists and is not a zombie.
bool running(pid_t pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/stat");
  std::string text;
  if (!std::getline(in, text)) return false;
  const size_t paren = text.rfind(')');
  return paren != std::string::npos && paren + 2 < text.size() && text[paren + 2] != 'Z';
}

TEST(FailurePaths, TetgenChildDiesWithItsParent) {
  // TetGen runs in a forked child; if om_dthex is killed (SIGKILL: no handler runs), the
  // child must not keep meshing for minutes: it has PR_SET_PDEATHSIG.
  if (!fs::exists("/proc/self/task/" + std::to_string(::getpid()) + "/children"))
    GTEST_SKIP() << "no /proc/<pid>/task/<pid>/children on this kernel";
  const dthex::TriSurface femur = dthex::read_surface(dthex_test::bundled_mesh("femur_proximal_ct.off"));  // TetGen takes > 10 s
  std::fflush(nullptr);
  const pid_t parent = ::fork();
  if (parent == 0) {
    dthex::tetrahedralize(femur, {"pq1.2Y", 600});
    ::_exit(0);
  }
  pid_t tetgen = 0;
  for (int i = 0; i < 200 && !tetgen; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    tetgen = first_child(parent);
  }
  ASSERT_NE(tetgen, 0) << "TetGen's process did not start";
  ASSERT_TRUE(running(tetgen));
  ::kill(parent, SIGKILL);
  ::waitpid(parent, nullptr, 0);
  bool gone = false;
  for (int i = 0; i < 200 && !gone; ++i) {
    gone = !running(tetgen);
    if (!gone) std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  if (!gone) ::kill(tetgen, SIGKILL);
  EXPECT_TRUE(gone) << "TetGen's process outlived its killed parent";
}

}  // namespace
