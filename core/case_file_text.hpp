// Case and included files up to the raw tree the validator checks: read only from regular files,
// checked for keys given twice (which yaml-cpp would keep one of, silently), syntax errors named
// by their cause, and included files merged in.
#pragma once

#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/schema.hpp"

namespace granflow::core {

// "a.b.c" -> {"a", "b", "c"} (empty parts kept: "a..b" has one).
std::vector<std::string> split_key_path(std::string_view path);

// Where the value at key `path` (the YAML `node`) came from: the --set or included file that gave
// it (`override_locations`, the last entry wins), else origin:line of the node, else origin.
std::string locate(const std::string& origin,
                   const std::vector<std::pair<std::string, std::string>>& override_locations,
                   const std::string& path, const YAML::Node& node);

// One --set key.path=value into the raw tree (`schema` names what a path runs into); recorded
// in `override_locations` as "--set key.path=value", where every error of it is located.
void apply_override(YAML::Node& raw, const std::string& item, const std::string& origin,
                    const Schema& schema,
                    std::vector<std::pair<std::string, std::string>>& override_locations);

// Case and included files are read only if they are regular files: a FIFO would block the
// open, a directory gives a library error. Checked before opening.
enum class ReadStatus { ok, cannot_open, not_regular };
ReadStatus read_regular_file(const std::filesystem::path& file, std::string& text);
// The case file's text; throws CaseError "FILE: cannot open ..." or "FILE: not a regular file".
std::string read_case_file(const std::filesystem::path& file);

struct DuplicateKey {
  std::string path;
  int line = 0, first_line = 0;
};
// The first key given twice in one mapping of the (first) document, or none; key paths start
// with `prefix`. Throws YAML::ParserException on a syntax error, as YAML::Load would.
std::optional<DuplicateKey> find_duplicate_key(const std::string& text, const std::string& prefix);
// Throws CaseError "FILE:LINE: key.path: given twice (first at line L); ..." for the first one.
void refuse_duplicate_keys(const std::string& text, const std::string& file);

// The YAML tree of a case or included file's text (`file` names it in messages), duplicate keys,
// keys that are lists or maps and a second document refused. A syntax error is a CaseError
// "FILE:LINE: YAML syntax error: ..." that names the cause where the parser's own text does not: a
// tab in the indentation (YAML indents with spaces; the parser stops later with "end of map not
// found"), or nesting deeper than its recursion limit.
YAML::Node load_case_yaml(const std::string& text, const std::string& file);
// A CaseError for the first key under `node` (at key path `path`) that is a list or a map
// (`[a]: 1`: YAML allows it, a case has key names only), located at `origin` plus the key's line
// when `in_file` (else `origin` is e.g. "--set key=value").
void refuse_complex_keys(const YAML::Node& node, const std::string& origin, bool in_file,
                         const std::string& path);

// `include: FILE` (or a list of files) of the case `raw` read from `origin`: the files' sections
// merged into `raw` (and `include` removed), each key's "file:line" appended to `locations`.
// A key given in both files is a CaseError naming both places; included files may not include.
void merge_includes(YAML::Node& raw, const std::string& origin,
                    std::vector<std::pair<std::string, std::string>>& locations);

}  // namespace granflow::core
