#include "reports/html.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace nightcap {

std::string format_number(double value, int digits) {
  if (std::isnan(value)) return "NaN";
  if (std::isinf(value)) return value > 0 ? "∞" : "−∞";
  std::ostringstream text;
  const double magnitude = std::abs(value);
  if (magnitude == 0.0 || magnitude < 1e-3 || magnitude >= 1e9) {
    text.precision(digits);
    text << value;
    return text.str();
  }
  // Fixed notation with `digits` significant digits, so that 1360 ms reads as 1360, not 1.36e+03.
  const int decimals = std::max(0, digits - 1 - int(std::floor(std::log10(magnitude))));
  text << std::fixed;
  text.precision(decimals);
  text << value;
  std::string fixed = text.str();
  if (fixed.find('.') != std::string::npos) {
    fixed.erase(fixed.find_last_not_of('0') + 1);
    if (fixed.back() == '.') fixed.pop_back();
  }
  return fixed;
}

std::string page_start(std::string_view title, bool with_script) {
  std::string html = "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n";
  html += kReportGenerator;
  html += "\n<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n<title>" + escape_markup(title) +
          "</title>\n<link rel=\"stylesheet\" href=\"report.css\">\n";
  if (with_script) html += "<script src=\"report.js\" defer></script>\n";
  return html + "</head>\n<body>\n";
}

void write_file(const std::filesystem::path& file, std::string_view text) {
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  out << text;
  if (!out.flush()) throw std::runtime_error(file.string() + ": cannot write");
}

void start_report_folder(const std::filesystem::path& folder) {
  if (std::filesystem::exists(folder) && !std::filesystem::is_empty(folder))
    throw std::runtime_error(folder.string() + ": exists and is not empty (the report writes a folder of its own)");
  std::filesystem::create_directories(folder);
}

void publish_page(const std::filesystem::path& folder, std::string_view html) {
  const std::filesystem::path partial = folder / "index.html.partial";
  write_file(partial, html);
  std::filesystem::rename(partial, folder / "index.html");
}

}  // namespace nightcap
