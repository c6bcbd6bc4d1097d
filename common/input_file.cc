#include "common/input_file.h"

#include <sys/stat.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>

#include "common/input_error.h"

namespace trav::common {

void RequireRegularFile(const std::string& path, std::size_t max_bytes) {
  if (path.empty()) throw InputError("", "", "an input file name is empty");
  struct stat status {};
  if (stat(path.c_str(), &status) != 0) {
    throw InputError(Excerpt(path, 200), "", std::string("cannot open: ") + std::strerror(errno));
  }
  if (S_ISDIR(status.st_mode)) throw InputError(Excerpt(path, 200), "", "is a folder, not a file");
  if (!S_ISREG(status.st_mode)) {
    throw InputError(Excerpt(path, 200), "", "is not a regular file (a FIFO, socket or device)");
  }
  if (static_cast<std::size_t>(status.st_size) > max_bytes) {
    throw InputError(Excerpt(path, 200), "",
                     "is " + std::to_string(status.st_size) + " bytes, more than the " +
                         std::to_string(max_bytes) + " trav reads");
  }
}

std::string ReadInputFile(const std::string& path, std::size_t max_bytes) {
  RequireRegularFile(path, max_bytes);
  std::ifstream file(path, std::ios::binary);
  if (!file) throw InputError(Excerpt(path, 200), "", "cannot open");
  std::ostringstream text;
  text << file.rdbuf();
  if (file.bad()) throw InputError(Excerpt(path, 200), "", "cannot read");
  return text.str();
}

}  // namespace trav::common
