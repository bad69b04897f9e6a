// Name checks shared by the metadata reader and the measured-data readers and writers.
// writers.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace flagella {
namespace identify {
namespace data_io {

bool contains(const std::vector<std::string>& names, const std::string& name);

/// Longest user text a message quotes whole where it is a list or a path (names and values are
/// cut at abbreviated()'s 60 characters).
constexpr size_t kMaxListedText = 300;

/// Empty if `name` is a valid override name "section.field[.more]", else what is wrong.
std::string overrideNameProblem(const std::string& name);

}  // namespace data_io
}  // namespace identify
}  // namespace flagella
