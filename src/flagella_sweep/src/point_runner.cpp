// One sweep point as a child process (point_runner.h).
#include "flagella_sweep/point_runner.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>

extern char** environ;

namespace flagella::sweep {

namespace {

namespace fs = std::filesystem;

/// Scalars of a JSON object, nested objects flattened with '.', arrays left out.
void flatten(const nlohmann::json& in, const std::string& prefix, nlohmann::json& out) {
  for (auto it = in.begin(); it != in.end(); ++it) {
    const std::string key = prefix.empty() ? it.key() : prefix + "." + it.key();
    if (it->is_object())
      flatten(*it, key, out);
    else if (!it->is_array())
      out[key] = *it;
  }
}

std::string lastLine(const std::string& file) {
  std::ifstream in(file);
  std::string line, last;
  while (std::getline(in, line))
    if (line.find_first_not_of(" \t\r") != std::string::npos) last = line;
  if (last.size() > 300) last = last.substr(0, 300) + "...";
  return last;
}

/// Runs argv with the working directory `cwd`, stdout and stderr into files; returns the exit
/// code (128 + signal if killed, 127 if it could not start).
int spawn(const std::vector<std::string>& argv, const std::string& cwd, const std::string& out,
          const std::string& err) {
  std::vector<char*> args;
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  // The tool is a process of its own, not a rank of this sweep's MPI job: without mpirun's
  // variables (with them, a tool that can use MPI would try to join the job and hang).
  std::vector<char*> env;
  for (char** e = environ; *e; ++e) {
    const std::string var(*e);
    if (var.rfind("OMPI_", 0) == 0 || var.rfind("PMI_", 0) == 0 || var.rfind("PMIX_", 0) == 0)
      continue;
    env.push_back(*e);
  }
  env.push_back(nullptr);
  const pid_t parent = getpid();
  const pid_t pid = fork();
  if (pid < 0) return 127;
  if (pid == 0) {                      // child: only async-signal-safe calls until exec
    prctl(PR_SET_PDEATHSIG, SIGTERM);  // a killed sweep takes its running points with it
    if (getppid() != parent) _exit(127);
    const int o = open(out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int e = open(err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (o < 0 || e < 0 || dup2(o, 1) < 0 || dup2(e, 2) < 0 || chdir(cwd.c_str()) != 0) _exit(127);
    execve(args[0], args.data(), env.data());
    _exit(127);
  }
  int status = 0;
  while (waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) return 127;
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  return WIFSIGNALED(status) ? 128 + WTERMSIG(status) : 127;
}

/// Exit codes that still carry a result: flagella_steer exits 4 when waypoints were missed.
bool resultExit(SweepTool tool, int code) {
  return code == 0 || (tool == SweepTool::Steer && code == 4);
}

}  // namespace

std::string executableDirectory() {
  std::error_code ec;
  const fs::path self = fs::read_symlink("/proc/self/exe", ec);
  return ec ? fs::current_path().string() : self.parent_path().string();
}

std::vector<std::string> toolCommand(const SweepSpec& spec, int index, const std::string& tool_dir,
                                     const std::string& work_dir, std::string& summary_file) {
  std::vector<std::string> argv;
  const std::string config = (fs::path(spec.directory) / spec.config).lexically_normal().string();
  switch (spec.tool) {
    case SweepTool::Run:
      argv = {tool_dir + "/flagella_run", "run", config, "--out", work_dir, "--quiet"};
      summary_file = work_dir + "/summary.json";
      break;
    case SweepTool::Buckling:
      summary_file = work_dir + "/result.json";
      argv = {tool_dir + "/flagella_buckling", config, "--json", summary_file, "--quiet"};
      break;
    case SweepTool::Steer:
      summary_file = work_dir + "/result.json";
      argv = {tool_dir + "/flagella_steer", "--config", config, "--json", summary_file};
      break;
  }
  for (const std::string& o : pointOverrides(spec, index)) {
    argv.push_back("--set");
    argv.push_back(o);
  }
  argv.insert(argv.end(), spec.args.begin(), spec.args.end());
  return argv;
}

nlohmann::json runPoint(const SweepSpec& spec, int index, const std::string& tool_dir,
                        const std::string& work_dir) {
  nlohmann::json record;
  record["index"] = index;
  nlohmann::json params = nlohmann::json::object();
  for (const auto& [field, value] : spec.points.at(static_cast<std::size_t>(index)))
    params[field] = value;
  record["params"] = params;
  std::error_code ec;
  fs::remove_all(work_dir, ec);
  fs::create_directories(work_dir, ec);
  std::string summary_file;
  const std::vector<std::string> argv = toolCommand(spec, index, tool_dir, work_dir, summary_file);
  const auto start = std::chrono::steady_clock::now();
  const int code =
      ec ? 127 : spawn(argv, spec.directory, work_dir + "/stdout.txt", work_dir + "/stderr.txt");
  record["wall_s"] =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  record["exit_code"] = code;
  nlohmann::json summary = nlohmann::json::object();
  std::string error;
  if (resultExit(spec.tool, code)) {
    std::ifstream in(summary_file);
    try {
      nlohmann::json parsed = nlohmann::json::parse(in);
      flatten(parsed, "", summary);
    } catch (const std::exception& e) {
      error = "no readable summary " + summary_file;
    }
  } else if (ec) {
    error = "cannot create " + work_dir + ": " + ec.message();
  } else {
    const std::string last = lastLine(work_dir + "/stderr.txt");
    error = "exit " + std::to_string(code) + (last.empty() ? "" : ": " + last);
  }
  record["status"] = error.empty() ? "ok" : "failed";
  record["error"] = error;
  record["summary"] = summary;
  return record;
}

}  // namespace flagella::sweep
