// The microbenchmarks' CSV files (gi-bench --rays, --refit, --refit-rebuild): rows appended run after run,
// the header written once, when the file is new.
#pragma once
#include <filesystem>
#include <fstream>
#include <string>

namespace tools {

// Opens `path` for appending rows into `out`, writing `header` (its column names and a newline) first where
// the file did not exist. False with `error` naming the file where it cannot be written.
bool appendResultsCsv(const std::filesystem::path& path, const char* header, std::ofstream& out, std::string& error);

}  // namespace tools
