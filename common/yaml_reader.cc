#include "common/yaml_reader.h"

#include <cmath>
#include <optional>
#include <sstream>

#include <yaml-cpp/yaml.h>

#include "common/input_file.h"

namespace trav::common {
namespace {

// A node as YAML text: a scalar's text, anything else in flow style.
std::string NodeText(const YAML::Node& node) {
  if (node.IsScalar()) return node.Scalar();
  YAML::Emitter emitter;
  emitter << YAML::Flow << node;
  return emitter.c_str();
}

// A node for error messages: a short excerpt of a scalar quoted, of anything else in flow style.
std::string ScalarText(const YAML::Node& node) {
  return node.IsScalar() ? QuotedExcerpt(node.Scalar()) : Excerpt(NodeText(node));
}

// True if `text` is valid UTF-8 without control characters (text a scenario may carry into file
// names, reports, plots and JSON).
bool IsPrintableUtf8(const std::string& text) {
  const auto at = [&](std::size_t i) { return static_cast<unsigned char>(text[i]); };
  for (std::size_t i = 0; i < text.size();) {
    const unsigned char byte = at(i);
    if (byte < 0x80) {
      if (byte < 0x20 || byte == 0x7f) return false;
      ++i;
      continue;
    }
    // RFC 3629: the length from the lead byte, and the range of the second byte that excludes
    // overlong forms, surrogates and code points above U+10FFFF
    int length = 0;
    unsigned char low = 0x80, high = 0xbf;
    if (byte >= 0xc2 && byte <= 0xdf) {
      length = 2;
    } else if (byte >= 0xe0 && byte <= 0xef) {
      length = 3;
      if (byte == 0xe0) low = 0xa0;
      if (byte == 0xed) high = 0x9f;
    } else if (byte >= 0xf0 && byte <= 0xf4) {
      length = 4;
      if (byte == 0xf0) low = 0x90;
      if (byte == 0xf4) high = 0x8f;
    } else {
      return false;
    }
    if (i + length > text.size()) return false;
    if (at(i + 1) < low || at(i + 1) > high) return false;
    for (int k = 2; k < length; ++k) {
      if (at(i + k) < 0x80 || at(i + k) > 0xbf) return false;
    }
    i += length;
  }
  return true;
}

// The text of a map key. @throws InputError if the key is not a scalar (a list or map as key).
std::string KeyText(const YAML::Node& key, const std::string& source, const std::string& path) {
  if (!key.IsScalar()) {
    throw InputError(source, path, "a key must be a name, got " + Excerpt(NodeText(key)));
  }
  return key.Scalar();
}

}  // namespace

YamlDocument::YamlDocument(std::unique_ptr<YAML::Node> root, std::string source)
    : root_(std::move(root)), source_(std::move(source)) {}
YamlDocument::YamlDocument(YamlDocument&&) noexcept = default;
YamlDocument& YamlDocument::operator=(YamlDocument&&) noexcept = default;
YamlDocument::~YamlDocument() = default;

YamlDocument YamlDocument::Load(const std::string& path) {
  const std::string text = ReadInputFile(path, "YAML file");
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw InputError(path, "", std::string("invalid YAML: ") + e.what());
  }
  if (!root.IsMap()) throw InputError(path, "", "expected a YAML map at the top level");
  return YamlDocument(std::make_unique<YAML::Node>(root), path);
}

YamlDocument YamlDocument::Parse(const std::string& text, const std::string& source_name) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw InputError(source_name, "", std::string("invalid YAML: ") + e.what());
  }
  if (!root.IsMap()) throw InputError(source_name, "", "expected a YAML map at the top level");
  return YamlDocument(std::make_unique<YAML::Node>(root), source_name);
}

YamlDocument YamlDocument::Empty(const std::string& source_name) {
  return YamlDocument(std::make_unique<YAML::Node>(YAML::NodeType::Map), source_name);
}

void YamlDocument::Set(const std::string& key_path, const std::string& value_text) {
  YAML::Node value;
  try {
    value = YAML::Load(value_text);
  } catch (const YAML::Exception& e) {
    throw InputError("--set", Excerpt(key_path),
                     "invalid value " + QuotedExcerpt(value_text) + ": " + e.what());
  }
  Assign(key_path, value);
}

void YamlDocument::SetString(const std::string& key_path, const std::string& value) {
  Assign(key_path, YAML::Node(value));
}

namespace {

// One element of a key path: a map key, and an item of the sequence under it ("name[i]").
struct PathStep {
  std::string key;
  std::optional<std::size_t> index;
};

std::vector<PathStep> ParseKeyPath(const std::string& key_path) {
  std::vector<PathStep> steps;
  std::stringstream stream(key_path);
  for (std::string key; std::getline(stream, key, '.');) {
    if (key.empty()) throw InputError("--set", Excerpt(key_path), "empty element in key path");
    PathStep step{key, std::nullopt};
    const std::size_t open = key.find('[');
    if (open != std::string::npos) {
      const std::string digits = key.substr(open + 1, key.size() - open - 2);
      if (key.back() != ']' || digits.empty() || digits.size() > 6 ||
          digits.find_first_not_of("0123456789") != std::string::npos || open == 0) {
        throw InputError(
            "--set", Excerpt(key_path),
            "expected name[index] with an index below 1000000 in " + QuotedExcerpt(key));
      }
      step.key = key.substr(0, open);
      step.index = std::stoul(digits);
    }
    steps.push_back(step);
  }
  if (steps.empty()) throw InputError("--set", Excerpt(key_path), "empty key path");
  return steps;
}

}  // namespace

std::optional<std::string> YamlDocument::Find(const std::string& key_path) const {
  YAML::Node node = YAML::Clone(*root_);
  for (const PathStep& step : ParseKeyPath(key_path)) {
    if (!node.IsMap()) return std::nullopt;
    YAML::Node child = node[step.key];
    if (!child.IsDefined()) return std::nullopt;
    if (step.index) {
      if (!child.IsSequence() || *step.index >= child.size()) return std::nullopt;
      child = child[*step.index];
    }
    node.reset(child);
  }
  return NodeText(node);
}

void YamlDocument::Assign(const std::string& key_path, const YAML::Node& value) {
  // Walk (and create) the maps along the path; yaml-cpp nodes are handles, so assignment below
  // writes into the tree. An element "name[i]" is item i of the existing sequence `name`.
  const std::vector<PathStep> steps = ParseKeyPath(key_path);
  YAML::Node node = *root_;
  for (std::size_t i = 0; i < steps.size(); ++i) {
    const PathStep& step = steps[i];
    const bool last = i + 1 == steps.size();
    if (step.index) {
      YAML::Node sequence = node[step.key];
      if (!sequence.IsSequence() || *step.index >= sequence.size()) {
        throw InputError("--set", Excerpt(key_path),
                         QuotedExcerpt(step.key) + " has no item " + std::to_string(*step.index));
      }
      if (last) {
        sequence[*step.index] = value;
        return;
      }
      YAML::Node item = sequence[*step.index];
      if (!item.IsMap())
        throw InputError("--set", Excerpt(key_path),
                         QuotedExcerpt(step.key) + " items are not maps");
      node.reset(item);
      continue;
    }
    if (last) {
      node[step.key] = value;
      return;
    }
    YAML::Node child = node[step.key];
    if (!child.IsDefined() || child.IsNull()) child = YAML::Node(YAML::NodeType::Map);
    if (!child.IsMap()) {
      throw InputError("--set", Excerpt(key_path), QuotedExcerpt(step.key) + " is not a map");
    }
    node[step.key] = child;
    node.reset(child);
  }
}

std::string YamlDocument::Dump() const {
  YAML::Emitter emitter;
  emitter << *root_;
  return std::string(emitter.c_str()) + "\n";
}

YamlReader YamlDocument::Root() const { return YamlReader(*root_, source_, ""); }

YamlReader::YamlReader(const YAML::Node& map, std::string source, std::string key_path)
    : map_(std::make_unique<YAML::Node>(map)),
      source_(std::move(source)),
      key_path_(std::move(key_path)) {}
YamlReader::YamlReader(const YamlReader& other)
    : map_(std::make_unique<YAML::Node>(*other.map_)),
      source_(other.source_),
      key_path_(other.key_path_),
      read_keys_(other.read_keys_) {}
YamlReader::YamlReader(YamlReader&&) noexcept = default;
YamlReader::~YamlReader() = default;

std::string YamlReader::PathOf(const std::string& key) const {
  return key_path_.empty() ? key : key_path_ + "." + key;
}

void YamlReader::Fail(const std::string& key, const std::string& what) const {
  throw InputError(source_, PathOf(key), what);
}

bool YamlReader::Has(const std::string& key) const {
  return map_->IsMap() && (*map_)[key].IsDefined();
}

YAML::Node YamlReader::Get(const std::string& key) {
  read_keys_.insert(key);
  return (*map_)[key];
}

void YamlReader::Check(const std::string& key, bool condition,
                       const std::string& expectation) const {
  if (condition) return;
  const YAML::Node value = (*map_)[key];
  Fail(key, "value " + (value.IsDefined() ? ScalarText(value) : "(default)") + " " + expectation);
}

namespace {

template <typename T>
void ReadScalar(YamlReader* reader, const YAML::Node& node, const std::string& key,
                const char* type_name, T* value) {
  if (!node.IsScalar())
    reader->Fail(key, "expected " + std::string(type_name) + ", got " + ScalarText(node));
  try {
    *value = node.as<T>();
  } catch (const YAML::Exception&) {
    reader->Fail(key, "expected " + std::string(type_name) + ", got " + ScalarText(node));
  }
}

}  // namespace

void YamlReader::Read(const std::string& key, double* value) {
  if (!Has(key)) return;
  const YAML::Node node = Get(key);
  double read = 0.0;
  ReadScalar(this, node, key, "a finite number", &read);
  if (!std::isfinite(read)) Fail(key, "expected a finite number, got " + ScalarText(node));
  *value = read;
}

void YamlReader::Read(const std::string& key, int* value) {
  if (!Has(key)) return;
  ReadScalar(this, Get(key), key, "an integer", value);
}

void YamlReader::Read(const std::string& key, std::uint64_t* value) {
  if (!Has(key)) return;
  const YAML::Node& node = Get(key);
  if (node.IsScalar() && !node.Scalar().empty() && node.Scalar()[0] == '-') {
    Fail(key, "expected a non-negative integer, got " + ScalarText(node));
  }
  ReadScalar(this, node, key, "a non-negative integer", value);
}

void YamlReader::Read(const std::string& key, bool* value) {
  if (!Has(key)) return;
  ReadScalar(this, Get(key), key, "true or false", value);
}

void YamlReader::Read(const std::string& key, std::string* value) {
  if (!Has(key)) return;
  const YAML::Node node = Get(key);
  std::string read;
  ReadScalar(this, node, key, "a string", &read);
  if (!IsPrintableUtf8(read)) {
    Fail(key, "expected printable UTF-8 text, got " + ScalarText(node));
  }
  *value = std::move(read);
}

namespace {

template <int N>
void ReadVector(YamlReader* reader, const YAML::Node& node, const std::string& key,
                Eigen::Matrix<double, N, 1>* value) {
  const std::string expected = "expected a sequence of " + std::to_string(N) + " numbers";
  if (!node.IsSequence() || node.size() != static_cast<std::size_t>(N)) {
    reader->Fail(key, expected + ", got " + ScalarText(node));
  }
  Eigen::Matrix<double, N, 1> result;
  for (int i = 0; i < N; ++i) {
    try {
      result[i] = node[i].as<double>();
    } catch (const YAML::Exception&) {
      reader->Fail(key, expected + ", got " + ScalarText(node));
    }
    if (!std::isfinite(result[i])) {
      reader->Fail(key, expected + " (finite), got " + ScalarText(node));
    }
  }
  *value = result;
}

}  // namespace

void YamlReader::Read(const std::string& key, Eigen::Vector2d* value) {
  if (!Has(key)) return;
  ReadVector<2>(this, Get(key), key, value);
}

void YamlReader::Read(const std::string& key, Eigen::Vector3d* value) {
  if (!Has(key)) return;
  ReadVector<3>(this, Get(key), key, value);
}

void YamlReader::Read(const std::string& key, Eigen::Matrix<double, 6, 1>* value) {
  if (!Has(key)) return;
  ReadVector<6>(this, Get(key), key, value);
}

void YamlReader::Read(const std::string& key, std::vector<Eigen::Vector2d>* value) {
  if (!Has(key)) return;
  const YAML::Node node = Get(key);
  if (!node.IsSequence())
    Fail(key, "expected a sequence of [x, y] points, got " + ScalarText(node));
  std::vector<Eigen::Vector2d> points(node.size());
  for (std::size_t i = 0; i < node.size(); ++i) {
    ReadVector<2>(this, node[i], key + "[" + std::to_string(i) + "]", &points[i]);
  }
  *value = std::move(points);
}

YamlReader YamlReader::Map(const std::string& key) {
  if (!Has(key)) Fail(key, "required map is missing");
  const YAML::Node node = Get(key);
  if (!node.IsMap()) Fail(key, "expected a map, got " + ScalarText(node));
  return YamlReader(node, source_, PathOf(key));
}

std::vector<YamlReader> YamlReader::MapSequence(const std::string& key) {
  std::vector<YamlReader> items;
  if (!Has(key)) return items;
  const YAML::Node node = Get(key);
  if (!node.IsSequence()) Fail(key, "expected a sequence, got " + ScalarText(node));
  for (std::size_t i = 0; i < node.size(); ++i) {
    const std::string item_path = PathOf(key) + "[" + std::to_string(i) + "]";
    if (!node[i].IsMap()) {
      throw InputError(source_, item_path, "expected a map, got " + ScalarText(node[i]));
    }
    items.emplace_back(node[i], source_, item_path);
  }
  return items;
}

void YamlReader::Read(const std::string& key, std::vector<std::string>* value) {
  if (!Has(key)) return;
  const YAML::Node node = Get(key);
  if (!node.IsSequence()) Fail(key, "expected a sequence, got " + ScalarText(node));
  value->clear();
  for (const YAML::Node& element : node) {
    value->push_back(NodeText(element));
    if (!IsPrintableUtf8(value->back())) {
      Fail(key, "expected printable UTF-8 text, got " + QuotedExcerpt(value->back()));
    }
  }
}

void YamlReader::ReadText(const std::string& key, std::string* value) {
  if (!Has(key)) return;
  *value = NodeText(Get(key));
  if (!IsPrintableUtf8(*value))
    Fail(key, "expected printable UTF-8 text, got " + QuotedExcerpt(*value));
}

std::vector<std::string> YamlReader::Keys() const {
  std::vector<std::string> keys;
  if (!map_->IsMap()) return keys;
  for (const auto& entry : *map_) keys.push_back(KeyText(entry.first, source_, key_path_));
  return keys;
}

void YamlReader::Finish() const {
  if (!map_->IsMap()) return;
  // yaml-cpp keeps repeated keys (and lookups see the first): reject them
  std::set<std::string> seen;
  for (const auto& entry : *map_) {
    const std::string key = KeyText(entry.first, source_, key_path_);
    if (!seen.insert(key).second) Fail(key, "duplicate key");
    if (read_keys_.count(key) == 0) Fail(key, "unknown key");
  }
}

}  // namespace trav::common
