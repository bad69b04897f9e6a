#include "flagella_sim/core/strict_yaml.h"

#include <yaml-cpp/eventhandler.h>

#include <cctype>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <vector>

#include "flagella_sim/core/text_lists.h"

namespace flagella {

namespace {

std::string located(const std::string& source, int line, int column, const std::string& message) {
  std::string where = source;
  if (line > 0) where += ": line " + std::to_string(line);
  if (line > 0 && column > 0) where += ", column " + std::to_string(column);
  return where + ": " + message;
}

int lineOf(const YAML::Node& node) { return node.Mark().is_null() ? 0 : node.Mark().line + 1; }
int columnOf(const YAML::Node& node) { return node.Mark().is_null() ? 0 : node.Mark().column + 1; }

// A tag this reader accepts: none, the non-specific "?" and "!", or a YAML core schema tag
// (!!str, !!int, ... = tag:yaml.org,2002:...).
bool standardTag(const std::string& tag) {
  return tag.empty() || tag == "?" || tag == "!" || tag.rfind("tag:yaml.org,2002:", 0) == 0;
}

// How a message names the node at `path` (a long path cut: messages quote user text short).
std::string named(const std::string& path) {
  return path.empty() ? "the document" : "'" + abbreviated(path, 200) + "'";
}

// The checks of checkStrictYaml over one tree. An alias is its anchor's node itself: a node
// met again is not checked again (chains of aliases to aliases would take exponential time),
// and a node met inside itself (an alias within its own anchor, "&a [*a]") is an error, not
// endless recursion.
class StrictCheck {
 public:
  explicit StrictCheck(const std::string& source) : source_(source) {}

  void check(const YAML::Node& node, const std::string& path) {
    if (!standardTag(node.Tag()))
      throw YamlInputError(source_, lineOf(node), columnOf(node),
                           "application tag '" + abbreviated(node.Tag()) + "' on " + named(path) +
                               " is not supported (only plain YAML values)");
    if (!node.IsSequence() && !node.IsMap()) return;
    if (const bool* done = met(node)) {
      if (*done) return;
      throw YamlInputError(
          source_, lineOf(node), columnOf(node),
          named(path) + " refers to a value that contains it (an alias inside its anchor)");
    }
    bool& done = met_.emplace(node.Mark().pos, std::make_pair(node, false))->second.second;
    if (node.IsSequence()) {
      int index = 0;
      for (const YAML::Node& item : node) check(item, path + "[" + std::to_string(index++) + "]");
    } else {
      checkMap(node, path);
    }
    done = true;
  }

 private:
  void checkMap(const YAML::Node& node, const std::string& path) {
    std::map<std::string, int> first_line;
    for (const auto& kv : node) {
      if (!kv.first.IsScalar())
        throw YamlInputError(source_, lineOf(kv.first), columnOf(kv.first),
                             "a key in " + named(path) + " is not a plain name");
      const std::string key = kv.first.Scalar();
      const std::string field = path.empty() ? abbreviated(key) : path + "." + abbreviated(key);
      const auto seen = first_line.find(key);
      if (seen != first_line.end())
        throw YamlInputError(source_, lineOf(kv.first), columnOf(kv.first),
                             "duplicate key " + named(field) + " (first given on line " +
                                 std::to_string(seen->second) + "); give each field once");
      first_line.emplace(key, lineOf(kv.first));
      check(kv.first, field);
      check(kv.second, field);
    }
  }

  // Whether `node` was met (its entry: true once checked), found by position, then identity.
  const bool* met(const YAML::Node& node) const {
    const auto [begin, end] = met_.equal_range(node.Mark().pos);
    for (auto it = begin; it != end; ++it)
      if (it->second.first.is(node)) return &it->second.second;
    return nullptr;
  }

  const std::string& source_;
  std::multimap<int, std::pair<YAML::Node, bool>> met_;  ///< collections met, by position
};

// Walks the documents of `text` without building them, to catch the input yaml-cpp's LoadAll
// never returns on: a ',' at the top level ("[1], [2]", ", a") stops the parser in front of it
// without consuming it, and every further call gives one more empty document until memory
// runs out (yaml-cpp 0.7). A document that starts where the previous one did is that case.
class DocumentStarts : public YAML::EventHandler {
 public:
  void OnDocumentStart(const YAML::Mark& mark) override { start_ = mark; }
  void OnDocumentEnd() override {}
  void OnNull(const YAML::Mark&, YAML::anchor_t) override {}
  void OnAlias(const YAML::Mark&, YAML::anchor_t) override {}
  void OnScalar(const YAML::Mark&, const std::string&, YAML::anchor_t,
                const std::string&) override {}
  void OnSequenceStart(const YAML::Mark&, const std::string&, YAML::anchor_t,
                       YAML::EmitterStyle::value) override {}
  void OnSequenceEnd() override {}
  void OnMapStart(const YAML::Mark&, const std::string&, YAML::anchor_t,
                  YAML::EmitterStyle::value) override {}
  void OnMapEnd() override {}
  const YAML::Mark& start() const { return start_; }

 private:
  YAML::Mark start_;
};

void rejectStuckParse(const std::string& text, const std::string& source) {
  std::istringstream stream(text);
  YAML::Parser parser(stream);
  DocumentStarts documents;
  int previous = -1;
  while (parser.HandleNextDocument(documents)) {
    const YAML::Mark& at = documents.start();
    if (at.pos <= previous) {
      const bool printable = at.pos >= 0 && at.pos < static_cast<int>(text.size()) &&
                             std::isgraph(static_cast<unsigned char>(text[at.pos]));
      throw YamlInputError(source, at.line + 1, at.column + 1,
                           "YAML syntax error: unexpected " +
                               (printable ? "'" + text.substr(at.pos, 1) + "'" : "token") +
                               " outside a [list] or {map}");
    }
    previous = at.pos;
  }
}

// `null_allowed`: a document that is just null (~, null) is a value (a --set value meaning "the
// default"), not an empty file.
YAML::Node parseOneDocument(const std::string& text, const std::string& source,
                            const std::string& what, bool null_allowed) {
  std::vector<YAML::Node> docs;
  try {
    rejectStuckParse(text, source);
    docs = YAML::LoadAll(text);
  } catch (const YAML::ParserException& e) {
    throw YamlInputError(source, e.mark.line + 1, e.mark.column + 1, "YAML syntax error: " + e.msg);
  } catch (const YAML::Exception& e) {
    throw YamlInputError(source, 0, 0, std::string("cannot read the YAML: ") + e.what());
  }
  if (docs.empty() || (docs.size() == 1 && docs[0].IsNull() && !null_allowed))
    throw YamlInputError(source, 0, 0,
                         "the " + what + " is empty (no YAML document: only blanks or comments)");
  if (docs.size() > 1)
    throw YamlInputError(source, lineOf(docs[1]), 0,
                         "holds " + std::to_string(docs.size()) +
                             " YAML documents (separated by '---'); give the " + what +
                             " as one document");
  checkStrictYaml(docs[0], source);
  return docs[0];
}

}  // namespace

YamlInputError::YamlInputError(const std::string& source, int line, int column,
                               const std::string& message)
    : ConfigError(located(source, line, column, message)),
      source_(source),
      line_(line),
      column_(column),
      message_(message) {}

YAML::Node loadStrictYamlFile(const std::string& path, const std::string& what) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    throw YamlInputError(
        path, 0, 0,
        "cannot open the " + what + " file (" +
            (std::filesystem::exists(path, ec) ? "not a regular file" : "no such file") + ")");
  std::ifstream file(path, std::ios::binary);
  if (!file) throw YamlInputError(path, 0, 0, "cannot open the " + what + " file");
  std::ostringstream text;
  text << file.rdbuf();
  if (file.bad()) throw YamlInputError(path, 0, 0, "cannot read the " + what + " file");
  return parseOneDocument(text.str(), path, what + " file", false);
}

YAML::Node loadStrictYamlText(const std::string& text, const std::string& source) {
  return parseOneDocument(text, source, "value", true);
}

void checkStrictYaml(const YAML::Node& root, const std::string& source) {
  StrictCheck(source).check(root, "");
}

}  // namespace flagella
