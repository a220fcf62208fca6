#include "core/file_io.hpp"

#include <H5Cpp.h>
#include <fcntl.h>
#include <fmt/format.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>

namespace granflow::core {

IoError::IoError(const std::filesystem::path& path_, const std::string& action,
                 const std::string& reason)
    : std::runtime_error(fmt::format("{}: {}: {}", path_.string(), action, reason)), path(path_) {}

void write_text_file(const std::filesystem::path& file, std::string_view text) {
  const std::filesystem::path temporary =
      file.parent_path() / fmt::format(".{}.{}.tmp", file.filename().string(), ::getpid());
  const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw IoError(file, "cannot create", std::strerror(errno));
  const auto fail = [&](const char* action) {
    const int err = errno;
    ::close(fd);
    ::unlink(temporary.c_str());
    throw IoError(file, action, std::strerror(err));
  };
  std::size_t done = 0;
  while (done < text.size()) {
    const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
    if (n < 0) {
      if (errno == EINTR) continue;
      fail("cannot write");
    }
    done += static_cast<std::size_t>(n);
  }
  // A full disk may show only here (delayed allocation) or at close.
  if (::fsync(fd) != 0 && errno != EINVAL && errno != EROFS) fail("cannot write");
  if (::close(fd) != 0) {
    const int err = errno;
    ::unlink(temporary.c_str());
    throw IoError(file, "cannot write", std::strerror(err));
  }
  if (::rename(temporary.c_str(), file.c_str()) != 0) {
    const int err = errno;
    ::unlink(temporary.c_str());
    throw IoError(file, "cannot replace", std::strerror(err));
  }
}

namespace {

thread_local std::string recorded_reason;

herr_t record_innermost(unsigned n, const H5E_error2_t* error, void*) {
  // The first failure since the last hdf5_failure_reason() is the cause; closing objects while
  // the exception unwinds may fail after it with less to say.
  if (n != 0 || error == nullptr || error->desc == nullptr || !recorded_reason.empty()) return 0;
  // HDF5's file drivers quote the system's message as "error message = '...'".
  const std::string desc = error->desc;
  const std::string tag = "error message = '";
  if (const auto at = desc.find(tag); at != std::string::npos) {
    const auto begin = at + tag.size();
    const auto end = desc.find('\'', begin);
    recorded_reason =
        desc.substr(begin, end == std::string::npos ? std::string::npos : end - begin);
  } else {
    recorded_reason = desc;
  }
  return 0;
}

herr_t record_failure(hid_t stack, void*) {
  H5Ewalk2(stack, H5E_WALK_UPWARD, record_innermost, nullptr);
  return 0;
}

}  // namespace

void install_hdf5_error_recorder() { H5Eset_auto2(H5E_DEFAULT, record_failure, nullptr); }

std::string hdf5_failure_reason() {
  std::string reason = std::move(recorded_reason);
  recorded_reason.clear();
  return reason.empty() ? std::string("HDF5 error") : reason;
}

namespace {
std::atomic<bool> abandoned{false};
}
void abandon_hdf5_file() { abandoned = true; }
bool hdf5_file_abandoned() { return abandoned; }

std::string describe_exception(std::exception_ptr error) {
  try {
    if (error) std::rethrow_exception(error);
    return "unknown error";
  } catch (const H5::Exception& e) {
    return fmt::format("HDF5: {} ({})", e.getDetailMsg(), hdf5_failure_reason());
  } catch (const std::exception& e) {
    return e.what();
  } catch (...) {
    return "unknown exception";
  }
}

}  // namespace granflow::core
