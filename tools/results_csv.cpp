#include "results_csv.h"

namespace tools {

bool appendResultsCsv(const std::filesystem::path& path, const char* header, std::ofstream& out, std::string& error) {
  const bool fresh = !std::filesystem::exists(path);
  out.open(path, std::ios::app);
  if (!out) {
    error = path.string() + ": cannot write";
    return false;
  }
  if (fresh) out << header;
  return true;
}

}  // namespace tools
