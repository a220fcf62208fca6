// The text of case and included files before yaml-cpp loads it: read only from regular files,
// and checked for keys given twice (which yaml-cpp would keep one of, silently).
#pragma once

#include <filesystem>
#include <optional>
#include <string>

namespace granflow::core {

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

}  // namespace granflow::core
