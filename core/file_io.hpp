// Output files that fail loudly: every write failure is one IoError line naming the path, what
// was being done and the system's reason ("No space left on device", "Permission denied"); the
// CLI turns it into exit code 5 and never into an abort or a "finished".
#pragma once

#include <exception>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>

namespace granflow::core {

class IoError : public std::runtime_error {
 public:
  // "PATH: ACTION: REASON"
  IoError(const std::filesystem::path& path, const std::string& action, const std::string& reason);
  std::filesystem::path path;
};

// Writes `text` to `file` through a temporary file beside it, flushed and renamed over `file`,
// so that a reader sees either the previous file or the whole new one (never a truncated one).
// Throws IoError with strerror(errno) when any step fails; the temporary is removed.
void write_text_file(const std::filesystem::path& file, std::string_view text);

// HDF5 reports a failed system call (write, open) deep in its error stack, which the C++ API's
// exception does not carry. install_hdf5_error_recorder() replaces HDF5's automatic printing
// (also what H5::Exception::dontPrint() turns off) by a recorder of the innermost message of
// each failure; hdf5_failure_reason() returns it ("No space left on device" when HDF5 quoted
// the system's message, else HDF5's own words) and clears it. Both are idempotent and cheap.
void install_hdf5_error_recorder();
std::string hdf5_failure_reason();

// After a file that failed to write (a full disk) could not be closed, HDF5's own shutdown at
// process exit crashes on it (H5F__close_cb): the file is let go (abandon_hdf5_file), and the
// CLI then ends the process without running exit handlers (std::_Exit) once its logs are out.
void abandon_hdf5_file();
bool hdf5_file_abandoned();

// One line for any exception, HDF5's own (not a std::exception) included.
std::string describe_exception(std::exception_ptr error);

}  // namespace granflow::core
