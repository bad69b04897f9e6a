// The Slurm backend (backends.h): an sbatch array script, one task per missing point.
#include <filesystem>
#include <fstream>
#include <sstream>

#include "flagella_sweep/backends.h"
#include "flagella_sweep/point_runner.h"

namespace flagella::sweep {

namespace {

namespace fs = std::filesystem;

/// A word quoted for bash (single quotes).
std::string shellQuoted(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += (c == '\'') ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

}  // namespace

std::string arrayRanges(const std::vector<int>& indices) {
  std::ostringstream out;
  for (std::size_t i = 0; i < indices.size();) {
    std::size_t j = i;
    while (j + 1 < indices.size() && indices[j + 1] == indices[j] + 1) ++j;
    out << (i ? "," : "") << indices[i];
    if (j > i) out << "-" << indices[j];
    i = j + 1;
  }
  return out.str();
}

std::string writeSlurmScript(const SweepSpec& spec, const SweepStore& store,
                             const std::vector<std::string>& extra_sbatch, int max_running) {
  const std::vector<int> todo = store.missing(static_cast<int>(spec.points.size()));
  const std::string out = fs::absolute(store.directory()).lexically_normal().string();
  const std::string sweep = fs::absolute(spec.file).lexically_normal().string();
  const std::string self = executableDirectory() + "/flagella_sweep";
  fs::create_directories(out + "/slurm");
  std::ostringstream s;
  s << "#!/bin/bash\n"
    << "# flagella_sweep: one Slurm array task per point of " << sweep << " still missing in\n"
    << "# " << out << ". Submit with `sbatch " << out << "/sweep.sbatch`; when the array has\n"
    << "# finished, build the table with `flagella_sweep collect " << sweep << " --out " << out
    << "`.\n"
    << "#SBATCH --job-name=flagella-sweep-" << fs::path(sweep).stem().string() << "\n"
    << "#SBATCH --array=" << arrayRanges(todo);
  if (max_running > 0) s << "%" << max_running;
  s << "\n"
    << "#SBATCH --ntasks=1\n"
    << "#SBATCH --cpus-per-task=1\n"
    << "#SBATCH --output=" << out << "/slurm/%A_%a.log\n";
  for (const std::string& line : extra_sbatch) s << "#SBATCH " << line << "\n";
  s << "set -euo pipefail\n"
    << "exec " << shellQuoted(self) << " run-point " << shellQuoted(sweep) << " --out "
    << shellQuoted(out) << " --index \"${SLURM_ARRAY_TASK_ID:?set by Slurm}\"\n";
  const std::string path = out + "/sweep.sbatch";
  std::ofstream file(path, std::ios::trunc);
  file << s.str();
  file.close();
  fs::permissions(path, fs::perms::owner_exec | fs::perms::group_exec | fs::perms::others_exec,
                  fs::perm_options::add);
  return path;
}

}  // namespace flagella::sweep
