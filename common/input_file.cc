#include "common/input_file.h"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>

#include <sys/stat.h>

#include "common/input_error.h"

namespace trav::common {

void RequireRegularFile(const std::string& path, const std::string& what, std::size_t max_bytes) {
  const std::string name = Excerpt(path, 200);
  if (path.empty()) throw InputError("", "", "the " + what + " file name is empty");
  struct stat status {};
  if (stat(path.c_str(), &status) != 0) {
    throw InputError(name, "", "cannot open " + what + ": " + std::strerror(errno));
  }
  if (S_ISDIR(status.st_mode)) throw InputError(name, "", "is a folder, not a " + what);
  if (!S_ISREG(status.st_mode)) {
    throw InputError(name, "", "is not a regular file (a FIFO, socket or device), not a " + what);
  }
  if (static_cast<std::size_t>(status.st_size) > max_bytes) {
    throw InputError(name, "",
                     "is " + std::to_string(status.st_size) + " bytes, more than the " +
                         std::to_string(max_bytes) + " trav reads as a " + what);
  }
}

std::string ReadInputFile(const std::string& path, const std::string& what, std::size_t max_bytes) {
  RequireRegularFile(path, what, max_bytes);
  std::ifstream file(path, std::ios::binary);
  if (!file) throw InputError(Excerpt(path, 200), "", "cannot open " + what);
  std::ostringstream text;
  text << file.rdbuf();
  if (file.bad()) throw InputError(Excerpt(path, 200), "", "cannot read " + what);
  return text.str();
}

}  // namespace trav::common
