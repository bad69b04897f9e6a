// Shared by the fuzz targets: a scratch folder for the files a reader opens, and the contract
// check (only ConfigError and its subclasses may escape a reader; anything else aborts).
#pragma once

#include <cxxabi.h>
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <typeinfo>

#include "flagella_sim/core/parameter_set.h"

namespace fuzz {

/// Longest error message a reader may give ("a few kB"): user text must be abbreviated.
constexpr size_t kMaxMessageBytes = 4096;

/// A folder of its own under $TMPDIR (or /tmp) for this process, removed at a normal exit.
class ScratchDir {
 public:
  ScratchDir() {
    const char* tmp = std::getenv("TMPDIR");
    std::string pattern = std::string(tmp && *tmp ? tmp : "/tmp") + "/flagella_fuzz.XXXXXX";
    if (!mkdtemp(pattern.data())) {
      std::perror("fuzz: mkdtemp");
      std::abort();
    }
    path_ = pattern;
  }
  ~ScratchDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  const std::string& path() const { return path_; }
  std::string file(const std::string& name) const { return path_ + "/" + name; }

 private:
  std::string path_;
};

/// Writes `size` bytes to `path` (replacing it); aborts if it cannot (the harness is broken).
inline void writeFile(const std::string& path, const void* data, size_t size) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(static_cast<const char*>(data), static_cast<std::streamsize>(size));
  out.close();
  if (!out) {
    std::fprintf(stderr, "fuzz: cannot write %s\n", path.c_str());
    std::abort();
  }
}
inline void writeFile(const std::string& path, const std::string& text) {
  writeFile(path, text.data(), text.size());
}

inline std::string typeName(const std::type_info& type) {
  int status = 0;
  std::unique_ptr<char, void (*)(void*)> name(
      abi::__cxa_demangle(type.name(), nullptr, nullptr, &status), std::free);
  return status == 0 && name ? name.get() : type.name();
}

[[noreturn]] inline void defect(const std::string& kind, const std::string& what) {
  std::fprintf(stderr, "\nfuzz: DEFECT: %s: %s\n", kind.c_str(), what.c_str());
  std::fflush(stderr);
  std::abort();
}

/// A ConfigError must say something, and not echo a long input whole.
/// FLAGELLA_FUZZ_VERBOSE=1 prints it (to see what a reproducer or a seed is told).
inline void checkMessage(const flagella::ConfigError& e) {
  const std::string message = e.what();
  static const bool verbose = std::getenv("FLAGELLA_FUZZ_VERBOSE") != nullptr;
  if (verbose) std::fprintf(stderr, "fuzz: %s: %s\n", typeName(typeid(e)).c_str(), e.what());
  if (message.empty()) defect(typeName(typeid(e)), "empty error message");
  if (message.size() > kMaxMessageBytes)
    defect(typeName(typeid(e)), "error message of " + std::to_string(message.size()) +
                                    " bytes (limit " + std::to_string(kMaxMessageBytes) +
                                    "), starting: " + message.substr(0, 300));
}

/// Runs `read`; ConfigError (DataError included) is the documented outcome of bad input, any
/// other exception escaping is a defect: its type and what() are printed, then abort().
template <class Read>
int expectOnlyConfigErrors(Read&& read) {
  try {
    read();
  } catch (const flagella::ConfigError& e) {
    checkMessage(e);
  } catch (const std::exception& e) {
    defect(typeName(typeid(e)), e.what());
  } catch (...) {
    const std::type_info* type = abi::__cxa_current_exception_type();
    defect(type ? typeName(*type) : "unknown exception", "(not a std::exception: no message)");
  }
  return 0;
}

}  // namespace fuzz
