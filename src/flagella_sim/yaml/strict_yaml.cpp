#include "flagella_sim/core/strict_yaml.h"

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <vector>

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

// How a message names the node at `path`.
std::string named(const std::string& path) {
  return path.empty() ? "the document" : "'" + path + "'";
}

void checkNode(const YAML::Node& node, const std::string& source, const std::string& path) {
  if (!standardTag(node.Tag()))
    throw YamlInputError(source, lineOf(node), columnOf(node),
                         "application tag '" + node.Tag() + "' on " + named(path) +
                             " is not supported (only plain YAML values)");
  if (node.IsSequence()) {
    int index = 0;
    for (const YAML::Node& item : node)
      checkNode(item, source, path + "[" + std::to_string(index++) + "]");
  } else if (node.IsMap()) {
    std::map<std::string, int> first_line;
    for (const auto& kv : node) {
      if (!kv.first.IsScalar())
        throw YamlInputError(source, lineOf(kv.first), columnOf(kv.first),
                             "a key in " + named(path) + " is not a plain name");
      const std::string key = kv.first.Scalar();
      const std::string field = path.empty() ? key : path + "." + key;
      const auto seen = first_line.find(key);
      if (seen != first_line.end())
        throw YamlInputError(source, lineOf(kv.first), columnOf(kv.first),
                             "duplicate key '" + field + "' (first given on line " +
                                 std::to_string(seen->second) + "); give each field once");
      first_line.emplace(key, lineOf(kv.first));
      checkNode(kv.first, source, field);
      checkNode(kv.second, source, field);
    }
  }
}

// `null_allowed`: a document that is just null (~, null) is a value (a --set value meaning "the
// default"), not an empty file.
YAML::Node parseOneDocument(const std::string& text, const std::string& source,
                            const std::string& what, bool null_allowed) {
  std::vector<YAML::Node> docs;
  try {
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
  checkNode(root, source, "");
}

}  // namespace flagella
