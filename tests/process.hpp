#pragma once
// Running programs from the tests without a shell: posix_spawnp with an argument vector, a working
// directory, extra environment variables and stdout/stderr captured in files; waiting with a
// deadline. Also the lookup of a program on PATH (to skip the MPI tests where mpirun is missing).
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

extern char** environ;

namespace slipfront::testing {

/// Whether `part` occurs in `s` (messages checked by their reason).
inline bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

inline std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// A program started in the background; its output goes to out_path and err_path.
struct Child {
  pid_t pid = -1;
  std::filesystem::path out_path, err_path;
};

/// Starts `args` (args[0] looked up on PATH) in `cwd` with `env` added to (or replacing entries of)
/// this process's environment; names in `unset` are removed.
inline Child spawn(const std::vector<std::string>& args, const std::filesystem::path& cwd,
                   const std::filesystem::path& out_path, const std::filesystem::path& err_path,
                   const std::map<std::string, std::string>& env = {}, const std::vector<std::string>& unset = {}) {
  std::vector<std::string> envs;
  for (char** e = environ; *e; ++e) {
    const std::string kv(*e);
    const std::string name = kv.substr(0, kv.find('='));
    bool drop = env.count(name) > 0;
    for (const auto& u : unset) drop |= u == name;
    if (!drop) envs.push_back(kv);
  }
  for (const auto& [k, v] : env) envs.push_back(k + "=" + v);
  std::vector<char*> argv, envp;
  for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  for (const auto& e : envs) envp.push_back(const_cast<char*>(e.c_str()));
  envp.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addchdir_np(&actions, cwd.c_str());
  const std::string out = std::filesystem::absolute(out_path).string(), err = std::filesystem::absolute(err_path).string();
  posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 1, out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_addopen(&actions, 2, err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  Child c;
  c.out_path = out;
  c.err_path = err;
  const int rc = posix_spawnp(&c.pid, argv[0], &actions, nullptr, argv.data(), envp.data());
  posix_spawn_file_actions_destroy(&actions);
  if (rc != 0) throw std::runtime_error("cannot start " + args[0]);
  return c;
}

/// Waits for the child at most `seconds` (then kills it with SIGKILL and returns -1); returns the
/// exit code, or 128 + signal.
inline int wait_for(const Child& c, double seconds) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  int status = 0;
  for (;;) {
    const pid_t r = ::waitpid(c.pid, &status, WNOHANG);
    if (r == c.pid) break;
    if (std::chrono::steady_clock::now() > deadline) {
      ::kill(c.pid, SIGKILL);
      ::waitpid(c.pid, &status, 0);
      return -1;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  if (WIFSIGNALED(status)) return 128 + WTERMSIG(status);
  return -1;
}

struct Output {
  int code = -1;
  std::string out, err;
};

/// Runs to the end (at most `seconds`): exit code and both streams.
inline Output run(const std::vector<std::string>& args, const std::filesystem::path& cwd,
                  const std::map<std::string, std::string>& env = {}, const std::vector<std::string>& unset = {},
                  double seconds = 300) {
  static int serial = 0;
  const std::string tag = std::to_string(::getpid()) + "-" + std::to_string(serial++);
  const auto tmp = std::filesystem::temp_directory_path();
  const Child c = spawn(args, cwd, tmp / ("slipfront-out-" + tag), tmp / ("slipfront-err-" + tag), env, unset);
  Output o;
  o.code = wait_for(c, seconds);
  o.out = slurp(c.out_path);
  o.err = slurp(c.err_path);
  std::filesystem::remove(c.out_path);
  std::filesystem::remove(c.err_path);
  return o;
}

/// `s` as one word of a POSIX shell (single quotes; a quote inside becomes '\'').
inline std::string shell_quote(const std::string& s) {
  std::string q = "'";
  for (const char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

inline void write_text(const std::filesystem::path& p, const std::string& text) {
  std::ofstream(p, std::ios::binary) << text;
}

struct ShellResult {
  int code = -1;           ///< the exit status (-1 when the shell did not exit normally)
  bool signalled = false;  ///< killed by a signal (the program or its shell)
  std::string out, err;
};

/// Runs `program args` in `dir` through bash, for command lines written as a user types them
/// (quotes, `--set 'models=[...]'`); `prefix` runs first in the same shell (e.g. "ulimit -f 64;").
/// Standard input is /dev/null; both streams are captured in `dir`.
inline ShellResult run_in_shell(const std::filesystem::path& dir, const std::string& program, const std::string& args,
                                const std::string& prefix = "") {
  const std::string cmd = "cd " + shell_quote(dir.string()) + " && " + prefix + " exec " + shell_quote(program) + " " +
                          args + " >" + shell_quote((dir / "stdout.txt").string()) + " 2>" +
                          shell_quote((dir / "stderr.txt").string()) + " </dev/null";
  const int status = std::system(("bash -c " + shell_quote(cmd)).c_str());
  ShellResult r;
  r.signalled = !WIFEXITED(status) || WEXITSTATUS(status) > 128;
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = slurp(dir / "stdout.txt");
  r.err = slurp(dir / "stderr.txt");
  return r;
}

/// The full path of `program` on PATH, or "" when it is not installed.
inline std::string find_program(const std::string& program) {
  const char* path = std::getenv("PATH");
  std::string p = path ? path : "";
  std::size_t start = 0;
  while (start <= p.size()) {
    const std::size_t end = std::min(p.find(':', start), p.size());
    const std::filesystem::path candidate = std::filesystem::path(p.substr(start, end - start)) / program;
    if (end > start && ::access(candidate.c_str(), X_OK) == 0) return candidate.string();
    start = end + 1;
  }
  return "";
}

/// Printed by a test that cannot run here (ctest marks it skipped: SKIP_REGULAR_EXPRESSION in
/// tests/CMakeLists.txt).
inline constexpr const char* skip_marker = "slipfront-test-skipped:";

}  // namespace slipfront::testing
