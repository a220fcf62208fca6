#include "core/case_file_text.hpp"

#include <fmt/format.h>
#include <yaml-cpp/eventhandler.h>
#include <yaml-cpp/yaml.h>

#include <fstream>
#include <map>
#include <sstream>
#include <system_error>
#include <vector>

#include "core/case.hpp"

namespace granflow::core {

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

}  // namespace granflow::core
