#pragma once

#include <string>

namespace trav::common {

/// One number formatted by a printf conversion for a double (for example "%.6g"), as reports and
/// CSV files write it.
std::string FormatNumber(const char* format, double value);

/// `text` with the characters that markup reserves escaped as entities (& < > " '), so that any
/// text (a file path, a run's parameter) can stand in an XML or HTML attribute or element.
std::string EscapeMarkup(const std::string& text);

}  // namespace trav::common
