#pragma once

#include <optional>
#include <string>
#include <string_view>

namespace trav::common {

/// One value of an enum and its name as written in scenario files, summaries and on the command
/// line.
template <typename Enum>
struct EnumName {
  Enum value;
  const char* name;
};

// Every enum with names has one table, declared beside the enum, and a function that finds it by
// argument-dependent lookup:
//
//   inline constexpr std::array<common::EnumName<Color>, 2> kColorNames{
//       {{Color::kRed, "red"}, {Color::kBlue, "blue"}}};
//   constexpr const auto& EnumNames(Color) { return kColorNames; }
//
// NameOf, EnumFromName and EnumNameList read that table: the summaries, the YAML archive and the
// command line cannot disagree on a name.

/// The name of `value` ("?" for a value outside its table).
template <typename Enum>
const char* NameOf(Enum value) {
  for (const auto& entry : EnumNames(value)) {
    if (entry.value == value) return entry.name;
  }
  return "?";
}

/// The value called `name`, or nothing.
template <typename Enum>
std::optional<Enum> EnumFromName(std::string_view name) {
  for (const auto& entry : EnumNames(Enum{})) {
    if (name == entry.name) return entry.value;
  }
  return std::nullopt;
}

/// Every name of the enum in table order, separated by ", " (for messages and help).
template <typename Enum>
std::string EnumNameList() {
  std::string list;
  for (const auto& entry : EnumNames(Enum{})) {
    list += (list.empty() ? "" : ", ") + std::string(entry.name);
  }
  return list;
}

}  // namespace trav::common
