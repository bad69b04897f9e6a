// Runs one point of a sweep: the point's tool as a child process (working directory: the sweep
// file's folder; output in the point's own work folder), then its JSON summary read back as a
// result record. The record is what every backend stores and gathers.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "flagella_sweep/sweep_spec.h"

namespace flagella::sweep {

/// The tool's command line for a point (argv[0] is the tool's absolute path), writing its
/// summary into `work_dir`; `summary_file` gets the JSON file the tool writes.
std::vector<std::string> toolCommand(const SweepSpec& spec, int index, const std::string& tool_dir,
                                     const std::string& work_dir, std::string& summary_file);

/// Runs point `index` with the tools in `tool_dir`, its files in `work_dir` (emptied first).
/// Never throws for a failing tool: the record says status "failed" with the exit code and the
/// last line of the tool's standard error. Record keys: index, params (field -> value text),
/// status ("ok" or "failed"), exit_code, error, wall_s, summary (the tool's JSON, scalars only,
/// nested keys joined with '.').
nlohmann::json runPoint(const SweepSpec& spec, int index, const std::string& tool_dir,
                        const std::string& work_dir);

/// The folder of the running executable (where the sibling tools are).
std::string executableDirectory();

}  // namespace flagella::sweep
