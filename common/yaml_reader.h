#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "common/enum_names.h"
#include "common/input_error.h"

namespace YAML {
class Node;
}  // namespace YAML

namespace trav::common {

class YamlReader;

/// A parsed YAML document with the name of its source (a file path or "<built-in>"), so every error
/// can name where the input came from. yaml-cpp stays out of this header.
class YamlDocument {
 public:
  /// @throws InputError if the file is missing or not valid YAML.
  static YamlDocument Load(const std::string& path);
  /// @throws InputError if `text` is not valid YAML.
  static YamlDocument Parse(const std::string& text, const std::string& source_name);
  /// A document holding an empty map (written in block style), to be filled with Set().
  static YamlDocument Empty(const std::string& source_name);

  YamlDocument(YamlDocument&&) noexcept;
  YamlDocument& operator=(YamlDocument&&) noexcept;
  ~YamlDocument();

  /// Sets the value at a dotted key path ("terrain.seed") from YAML text ("7", "[1, 2]"), creating
  /// maps on the way (the strict reader later rejects keys that do not exist). "name[i]" in the
  /// path is item i of an existing sequence ("controller.mpc.state_weights[2]", "drive[0].v").
  /// Used by `--set key=value`.
  /// @throws InputError if the value is not valid YAML, a path element is not a map, or an
  /// indexed sequence is missing or too short.
  void Set(const std::string& key_path, const std::string& value_text);

  /// Like Set(), but stores `value` as a string as it is (file paths with any characters).
  void SetString(const std::string& key_path, const std::string& value);

  /// The value at a key path (the syntax of Set()) as YAML text, or nothing if it is absent.
  std::optional<std::string> Find(const std::string& key_path) const;

  /// The document as YAML text.
  std::string Dump() const;

  /// A strict reader of the root map.
  YamlReader Root() const;

  const std::string& source() const { return source_; }

 private:
  YamlDocument(std::unique_ptr<YAML::Node> root, std::string source);
  void Assign(const std::string& key_path, const YAML::Node& value);
  std::unique_ptr<YAML::Node> root_;
  std::string source_;
};

/// Strict reader of one YAML map: every key must be read (an unknown key is an error when Finish()
/// is called), every value must have the expected type, and every error names the source, the key
/// path and the offending value. Keys that are absent leave the destination at its documented
/// default.
class YamlReader {
 public:
  YamlReader(const YAML::Node& map, std::string source, std::string key_path);
  YamlReader(const YamlReader&);
  YamlReader(YamlReader&&) noexcept;
  ~YamlReader();

  /// True if the map has `key`.
  bool Has(const std::string& key) const;

  /// Reads an optional scalar; leaves `*value` unchanged if the key is absent.
  /// @throws InputError on a wrong type.
  void Read(const std::string& key, double* value);
  void Read(const std::string& key, int* value);
  void Read(const std::string& key, std::uint64_t* value);
  void Read(const std::string& key, bool* value);
  void Read(const std::string& key, std::string* value);
  /// Reads a sequence of exactly 2, 3 or 6 numbers.
  void Read(const std::string& key, Eigen::Vector2d* value);
  void Read(const std::string& key, Eigen::Vector3d* value);
  void Read(const std::string& key, Eigen::Matrix<double, 6, 1>* value);
  /// Reads a sequence of points, each a sequence of 2 numbers ([[x, y], ...]).
  void Read(const std::string& key, std::vector<Eigen::Vector2d>* value);
  /// Reads a sequence as the YAML text of each element ("3", "hilly", "[80, 80, 4]").
  void Read(const std::string& key, std::vector<std::string>* value);

  /// Reads any value as YAML text (a scalar's text, or a sequence or map in flow style).
  void ReadText(const std::string& key, std::string* value);

  /// The keys of the map, in document order.
  std::vector<std::string> Keys() const;

  /// Reads an enum by the names of its table (common/enum_names.h); an unknown name is an error
  /// listing the valid ones.
  template <typename Enum>
  void ReadEnum(const std::string& key, Enum* value) {
    if (!Has(key)) return;
    std::string text;
    Read(key, &text);
    const std::optional<Enum> named = EnumFromName<Enum>(text);
    if (!named) {
      Fail(key, "unknown value '" + text + "' (expected one of: " + EnumNameList<Enum>() + ")");
    }
    *value = *named;
  }

  /// Like Read(), but the key must be present.
  template <typename T>
  void ReadRequired(const std::string& key, T* value) {
    if (!Has(key)) Fail(key, "required key is missing");
    Read(key, value);
  }

  /// A strict reader of the map under `key`. @throws InputError if it is absent or not a map.
  YamlReader Map(const std::string& key);

  /// Strict readers of each map in the sequence under `key` (empty if the key is absent).
  /// @throws InputError if it is not a sequence of maps.
  std::vector<YamlReader> MapSequence(const std::string& key);

  /// Throws InputError naming `key`, its value and `expectation` unless `condition` holds.
  void Check(const std::string& key, bool condition, const std::string& expectation) const;

  /// @throws InputError if the map has a key that was not read, or a key twice.
  void Finish() const;

  /// Throws InputError "<source>: <path>.<key>: <what>".
  [[noreturn]] void Fail(const std::string& key, const std::string& what) const;

  /// The dotted path of `key` in this map.
  std::string PathOf(const std::string& key) const;

 private:
  /// Marks `key` as read and returns its node.
  YAML::Node Get(const std::string& key);
  std::unique_ptr<YAML::Node> map_;
  std::string source_;
  std::string key_path_;
  std::set<std::string> read_keys_;
};

}  // namespace trav::common
