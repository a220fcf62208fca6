#include "core/case_file_text.hpp"

#include <fmt/format.h>
#include <yaml-cpp/depthguard.h>
#include <yaml-cpp/eventhandler.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>
#include <system_error>
#include <vector>

#include "core/case.hpp"

namespace granflow::core {

namespace {

// Length of the valid UTF-8 sequence at text[i], or 0.
std::size_t utf8_length(std::string_view text, std::size_t i) {
  const auto byte = [&](std::size_t k) { return static_cast<unsigned char>(text[k]); };
  const unsigned char c = byte(i);
  const std::size_t n = c < 0x80           ? 1
                        : (c >> 5) == 0x6  ? 2
                        : (c >> 4) == 0xE  ? 3
                        : (c >> 3) == 0x1E ? 4
                                           : 0;
  if (n == 0 || i + n > text.size()) return 0;
  for (std::size_t k = 1; k < n; ++k)
    if ((byte(i + k) >> 6) != 0x2) return 0;
  return n;
}

std::string one_line(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (std::size_t i = 0; i < text.size();) {
    const auto c = static_cast<unsigned char>(text[i]);
    const std::size_t n = utf8_length(text, i);
    if (c == '\n') {
      out += "\\n";
    } else if (c == '\t') {
      out += "\\t";
    } else if (n == 0 || c < 0x20 || c == 0x7F) {
      out += fmt::format("\\x{:02X}", c);
    } else {
      out.append(text.substr(i, n));
      i += n;
      continue;
    }
    ++i;
  }
  return out;
}

}  // namespace

CaseError::CaseError(const std::string& message) : std::runtime_error(one_line(message)) {}

std::string shorten(std::string_view text, std::size_t max_chars) {
  if (text.size() <= max_chars) return std::string(text);
  std::size_t cut = max_chars;
  while (cut > 0 && (static_cast<unsigned char>(text[cut]) >> 6) == 0x2) --cut;
  return std::string(text.substr(0, cut)) + "...";
}

std::vector<std::string> split_key_path(std::string_view path) {
  std::vector<std::string> parts;
  std::size_t start = 0;
  while (start <= path.size()) {
    const auto dot = path.find('.', start);
    const auto end = dot == std::string_view::npos ? path.size() : dot;
    parts.emplace_back(path.substr(start, end - start));
    if (dot == std::string_view::npos) break;
    start = dot + 1;
  }
  return parts;
}

// Where the value at `path` (the YAML `node`) came from: the --set or included file that gave it
// (the last entry wins: --set is recorded after the included files' keys), else origin:line.
std::string locate(const std::string& origin,
                   const std::vector<std::pair<std::string, std::string>>& override_locations,
                   const std::string& path, const YAML::Node& node) {
  for (auto it = override_locations.rbegin(); it != override_locations.rend(); ++it)
    if (it->first == path || path.rfind(it->first + ".", 0) == 0) return it->second;
  if (node.IsDefined() && node.Mark().line >= 0)
    return fmt::format("{}:{}", origin, node.Mark().line + 1);
  return origin;
}

namespace {

std::string join(const std::string& prefix, const std::string& key) {
  return prefix.empty() ? key : prefix + "." + key;
}

// yaml-cpp keeps one value of a key given twice in a mapping, silently. This pass over the
// events of the same parser the loader uses finds such keys exactly, at any depth: each open
// mapping keeps its keys with the line where each was first given.
class DuplicateKeyFinder : public YAML::EventHandler {
 public:
  explicit DuplicateKeyFinder(std::string prefix) : prefix_(std::move(prefix)) {}
  const std::optional<DuplicateKey>& found() const { return found_; }

  void OnDocumentStart(const YAML::Mark&) override {}
  void OnDocumentEnd() override {}
  void OnNull(const YAML::Mark& mark, YAML::anchor_t) override {
    const std::string null_key = "~";
    enter(mark, &null_key);
  }
  void OnAlias(const YAML::Mark& mark, YAML::anchor_t) override { enter(mark, nullptr); }
  void OnScalar(const YAML::Mark& mark, const std::string&, YAML::anchor_t,
                const std::string& value) override {
    enter(mark, &value);
  }
  void OnSequenceStart(const YAML::Mark& mark, const std::string&, YAML::anchor_t,
                       YAML::EmitterStyle::value) override {
    push(false, enter(mark, nullptr));
  }
  void OnSequenceEnd() override { stack_.pop_back(); }
  void OnMapStart(const YAML::Mark& mark, const std::string&, YAML::anchor_t,
                  YAML::EmitterStyle::value) override {
    push(true, enter(mark, nullptr));
  }
  void OnMapEnd() override { stack_.pop_back(); }

 private:
  struct Frame {
    bool map = false;
    std::string path;
    bool expect_key = true;
    std::string key;                  // the key whose value comes next
    std::map<std::string, int> keys;  // key -> line of its first occurrence
    std::size_t index = 0;            // sequence item
  };

  void push(bool map, std::string path) {
    Frame f;
    f.map = map;
    f.path = std::move(path);
    stack_.push_back(std::move(f));
  }

  // A node starts: returns its key path and advances the enclosing collection. `scalar` is its
  // text when it is a scalar (a key to check when the enclosing map expects a key).
  std::string enter(const YAML::Mark& mark, const std::string* scalar) {
    if (stack_.empty()) return prefix_;
    Frame& f = stack_.back();
    if (!f.map) return fmt::format("{}[{}]", f.path, f.index++);
    if (f.expect_key) {
      f.expect_key = false;
      f.key = scalar ? *scalar : "?";
      if (scalar && !found_) {
        const auto [it, inserted] = f.keys.emplace(*scalar, mark.line + 1);
        if (!inserted) found_ = DuplicateKey{join(f.path, *scalar), mark.line + 1, it->second};
      }
      return join(f.path, "?");  // a complex key's own content: not a case path
    }
    f.expect_key = true;
    return join(f.path, f.key);
  }

  std::string prefix_;
  std::vector<Frame> stack_;
  std::optional<DuplicateKey> found_;
};

}  // namespace

std::optional<DuplicateKey> find_duplicate_key(const std::string& text, const std::string& prefix) {
  std::istringstream in(text);
  YAML::Parser parser(in);
  DuplicateKeyFinder finder(prefix);
  parser.HandleNextDocument(finder);
  return finder.found();
}

void refuse_duplicate_keys(const std::string& text, const std::string& file) {
  if (const auto dup = find_duplicate_key(text, ""))
    throw CaseError(fmt::format("{}:{}: {}: given twice (first at line {}); expected each key once",
                                file, dup->line, dup->path, dup->first_line));
}

namespace {

// The first line (1-based) whose indentation holds a tab, or 0 (yaml-cpp refuses a tab there
// even on a blank or comment line).
int tab_indented_line(const std::string& text) {
  int line = 1;
  for (std::size_t start = 0; start < text.size(); ++line) {
    const auto end = std::min(text.find('\n', start), text.size());
    const auto content = std::min(text.find_first_not_of(" \t", start), end);
    if (text.find('\t', start) < content) return line;
    start = end + 1;
  }
  return 0;
}

}  // namespace

void refuse_complex_keys(const YAML::Node& node, const std::string& origin, bool in_file,
                         const std::string& path) {
  if (node.IsSequence()) {
    for (std::size_t i = 0; i < node.size(); ++i)
      refuse_complex_keys(node[i], origin, in_file, fmt::format("{}[{}]", path, i));
  } else if (node.IsMap()) {
    for (const auto& item : node) {
      if (!item.first.IsScalar() && !item.first.IsNull())
        throw CaseError(
            fmt::format("{}{}: {}: a key that is a list or a map; expected a key name", origin,
                        in_file ? fmt::format(":{}", item.first.Mark().line + 1) : std::string(),
                        path.empty() ? "(top level)" : path));
      refuse_complex_keys(item.second, origin, in_file, join(path, item.first.as<std::string>()));
    }
  }
}

YAML::Node load_case_yaml(const std::string& text, const std::string& file) {
  try {
    refuse_duplicate_keys(text, file);
    const std::vector<YAML::Node> documents = YAML::LoadAll(text);
    for (std::size_t i = 1; i < documents.size(); ++i)
      if (!documents[i].IsNull())
        throw CaseError(fmt::format(
            "{}:{}: YAML syntax error: a second document (after ---); expected one document per "
            "file",
            file, documents[i].Mark().line + 1));
    const YAML::Node root = documents.empty() ? YAML::Node() : documents.front();
    refuse_complex_keys(root, file, true, "");
    return root;
  } catch (const YAML::DeepRecursion& e) {
    throw CaseError(fmt::format(
        "{}:{}: YAML syntax error: nested too deeply (maps and lists inside one another beyond "
        "the parser's limit); a case file is a few sections deep",
        file, e.mark.line + 1));
  } catch (const YAML::ParserException& e) {
    const int tab = tab_indented_line(text);
    if (tab > 0 && tab <= e.mark.line + 1)
      throw CaseError(fmt::format(
          "{}:{}: YAML syntax error: a tab in the indentation; expected spaces (YAML indents "
          "with spaces only; the parser stopped at line {}: {})",
          file, tab, e.mark.line + 1, e.msg));
    throw CaseError(fmt::format("{}:{}: YAML syntax error: {}", file, e.mark.line + 1, e.msg));
  }
}

ReadStatus read_regular_file(const std::filesystem::path& file, std::string& text) {
  std::error_code ec;
  const auto status = std::filesystem::status(file, ec);
  if (ec || !std::filesystem::exists(status)) return ReadStatus::cannot_open;
  if (!std::filesystem::is_regular_file(status)) return ReadStatus::not_regular;
  std::ifstream in(file, std::ios::binary);
  if (!in) return ReadStatus::cannot_open;
  std::ostringstream buffer;
  buffer << in.rdbuf();
  if (in.bad()) return ReadStatus::cannot_open;
  text = buffer.str();
  return ReadStatus::ok;
}

std::string read_case_file(const std::filesystem::path& file) {
  std::string text;
  switch (read_regular_file(file, text)) {
    case ReadStatus::ok:
      break;
    case ReadStatus::cannot_open:
      throw CaseError(fmt::format("{}: cannot open the case file", file.string()));
    case ReadStatus::not_regular:
      throw CaseError(fmt::format("{}: not a regular file", file.string()));
  }
  return text;
}

// `include: FILE` (or a list of files), relative to the including file: their sections are merged
// into the case before validation, so a calibrated parameter file (kind: calibrate writes one)
// can be used by rev and mpm cases directly. A key given in both files is an error naming both
// places (no silent precedence); --set still overrides everything. Included files may not
// include further files.
namespace {

void merge_node(YAML::Node target, const YAML::Node& source, const std::string& path,
                const std::string& file, const std::string& origin,
                std::vector<std::pair<std::string, std::string>>& locations) {
  for (const auto& item : source) {
    const auto key = item.first.as<std::string>();
    const std::string child_path = join(path, key);
    const std::string where = fmt::format("{}:{}", file, item.first.Mark().line + 1);
    YAML::Node existing = target[key];
    if (existing.IsDefined() && existing.IsMap() && item.second.IsMap()) {
      merge_node(existing, item.second, child_path, file, origin, locations);
      continue;
    }
    if (existing.IsDefined())
      throw CaseError(
          fmt::format("{}: {}: given both here and in {}:{}; expected it in one file only", where,
                      child_path, origin, existing.Mark().line + 1));
    target[key] = item.second;
    std::function<void(const YAML::Node&, const std::string&)> record = [&](const YAML::Node& n,
                                                                            const std::string& p) {
      if (n.IsMap()) {
        for (const auto& sub : n) record(sub.second, join(p, sub.first.as<std::string>()));
      } else {
        locations.emplace_back(p, fmt::format("{}:{}", file, n.Mark().line + 1));
      }
    };
    record(item.second, child_path);
  }
}

}  // namespace

void merge_includes(YAML::Node& raw, const std::string& origin,
                    std::vector<std::pair<std::string, std::string>>& locations) {
  const YAML::Node include = raw["include"];
  if (!include.IsDefined()) return;
  const std::string at = fmt::format("{}:{}", origin, include.Mark().line + 1);
  std::vector<std::string> files;
  if (include.IsScalar()) {
    files.push_back(include.as<std::string>());
  } else if (include.IsSequence()) {
    for (const auto& f : include) {
      if (!f.IsScalar())
        throw CaseError(at + ": include: expected a file name or a list of file names");
      files.push_back(f.as<std::string>());
    }
  } else {
    throw CaseError(at + ": include: expected a file name or a list of file names");
  }
  raw.remove("include");
  const std::filesystem::path base = std::filesystem::path(origin).parent_path();
  for (const auto& name : files) {
    const std::filesystem::path file =
        std::filesystem::path(name).is_absolute() ? std::filesystem::path(name) : base / name;
    std::string text;
    switch (read_regular_file(file, text)) {
      case ReadStatus::ok:
        break;
      case ReadStatus::cannot_open:
        throw CaseError(
            fmt::format("{}: include: cannot open '{}'", at, shorten(file.string(), 200)));
      case ReadStatus::not_regular:
        throw CaseError(fmt::format("{}: not a regular file (included at {})",
                                    shorten(file.string(), 200), at));
    }
    const YAML::Node included = load_case_yaml(text, file.string());  // located in that file
    if (!included.IsMap())
      throw CaseError(
          fmt::format("{}:1: (top level): expected a map of case sections", file.string()));
    if (included["include"].IsDefined())
      throw CaseError(fmt::format("{}:{}: include: an included file may not include further files",
                                  file.string(), included["include"].Mark().line + 1));
    for (const char* header : {"kind", "test", "name"})
      if (included[header].IsDefined())
        throw CaseError(
            fmt::format("{}:{}: {}: not allowed in an included file; expected only "
                        "parameter sections",
                        file.string(), included[header].Mark().line + 1, header));
    merge_node(raw, included, "", file.string(), origin, locations);
  }
}

// One --set key.path=value into the raw tree; every error is located at the --set.
void apply_override(YAML::Node& raw, const std::string& item, const std::string& origin,
                    const Schema& schema,
                    std::vector<std::pair<std::string, std::string>>& override_locations) {
  const std::string at = "--set " + shorten(item);
  const auto eq = item.find('=');
  if (eq == std::string::npos || eq == 0)
    throw CaseError(fmt::format("{}: expected key.path=value", at));
  const std::string path = item.substr(0, eq);
  const auto parts = split_key_path(path);
  for (const auto& part : parts)
    if (part.empty())
      throw CaseError(fmt::format(
          "{}: {}: an empty key (two dots, or a dot at an end); expected key.path=value", at,
          shorten(path)));
  YAML::Node value;
  try {
    // a map value given on the command line follows the same rule as the file
    if (const auto dup = find_duplicate_key(item.substr(eq + 1), path))
      throw CaseError(
          fmt::format("{}: {}: given twice; expected each key once", at, shorten(dup->path)));
    value = YAML::Load(item.substr(eq + 1));
  } catch (const YAML::Exception& e) {
    throw CaseError(fmt::format("{}: the value is not valid YAML: {}", at, e.what()));
  }
  refuse_complex_keys(value, at, false, path);
  // sweep.<key.path>=[...]: the rest of the path is one sweep key (flat, as in the file)
  if (parts.front() == "sweep" && parts.size() > 1) {
    YAML::Node sweep = raw["sweep"];
    if (sweep.IsDefined() && !sweep.IsNull() && !sweep.IsMap())
      throw CaseError(fmt::format("{}: sweep: expected a map of key.path: [values]",
                                  locate(origin, override_locations, "sweep", sweep)));
    if (!sweep.IsDefined() || sweep.IsNull()) raw["sweep"] = YAML::Node(YAML::NodeType::Map);
    raw["sweep"][path.substr(6)] = value;
    override_locations.emplace_back(path, at);
    return;
  }
  std::vector<YAML::Node> chain{raw};
  for (std::size_t i = 0; i + 1 < parts.size(); ++i) {
    YAML::Node next = chain.back()[parts[i]];
    if (!next.IsDefined() || next.IsNull()) {
      chain.back()[parts[i]] = YAML::Node(YAML::NodeType::Map);
      next = chain.back()[parts[i]];
    } else if (!next.IsMap()) {
      std::string prefix = parts[0];
      for (std::size_t k = 1; k <= i; ++k) prefix += "." + parts[k];
      const Field* field = &schema;
      for (std::size_t k = 0; k <= i && field; ++k)
        field = field->type() == ValueType::section ? field->child(parts[k]) : nullptr;
      throw CaseError(
          fmt::format("{}: {}: unknown key; {} is {}, not a section of keys", at, path, prefix,
                      field ? "a " + std::string(to_string(field->type())) : "a value"));
    }
    chain.push_back(next);
  }
  chain.back()[parts.back()] = value;
  override_locations.emplace_back(path, at);
}

std::pair<std::string, std::string> peek_kind(const std::filesystem::path& file) {
  // a FIFO or directory is refused before opening, a syntax error named as Case::load names it
  const YAML::Node raw = load_case_yaml(read_case_file(file), file.string());
  if (!raw.IsMap() || !raw["kind"].IsDefined())
    throw CaseError(
        fmt::format("{}:1: kind: missing required key; expected the case kind "
                    "(rev, dem, mpm, pair, calibrate)",
                    file.string()));
  for (const auto& item : raw)  // located at the key: an empty value has no line of its own
    for (const char* key : {"kind", "test"})
      if (item.first.as<std::string>() == key && !item.second.IsScalar())
        throw CaseError(fmt::format("{}:{}: {}: expected a name, not a list, map or empty value",
                                    file.string(), item.first.Mark().line + 1, key));
  const std::string kind = raw["kind"].as<std::string>();
  const std::string test = raw["test"].IsDefined() ? raw["test"].as<std::string>() : "";
  // names only (the registry echoes them in its message)
  for (const auto& [key, value] : {std::pair{"kind", kind}, std::pair{"test", test}})
    if (value.size() > 64 ||
        value.find_first_not_of("abcdefghijklmnopqrstuvwxyz"
                                "ABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_-") != std::string::npos)
      throw CaseError(fmt::format("{}:{}: {}: '{}' is not a name; expected {}", file.string(),
                                  raw[key].Mark().line + 1, key, shorten(value, 40),
                                  key == std::string("kind")
                                      ? "the case kind (rev, dem, mpm, pair, calibrate)"
                                      : "the test of the kind (e.g. simple_shear)"));
  return {kind, test};
}

}  // namespace granflow::core
