#include "io/json_writer.hpp"

#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "io/atomic_file.hpp"

namespace dsdem::io {

namespace {

void newline_and_indent(std::string& out, int indent, int depth) {
  if (indent < 0) return;
  out += '\n';
  out.append(static_cast<std::size_t>(indent) * static_cast<std::size_t>(depth), ' ');
}

}  // namespace

std::string json_number(double d) {
  if (!std::isfinite(d)) return "null";
  std::string s = fmt::format("{}", d);  // shortest round-trip representation
  // "1" would read back as an integer in Python and JavaScript's typed consumers.
  if (s.find_first_of(".eE") == std::string::npos) s += ".0";
  return s;
}

std::string json_string(std::string_view s) {
  std::string out;
  out.reserve(s.size() + 2);
  out += '"';
  for (const char ch : s) {
    const auto c = static_cast<unsigned char>(ch);
    switch (c) {
      case '"': out += "\\\""; break;
      case '\\': out += "\\\\"; break;
      case '\b': out += "\\b"; break;
      case '\f': out += "\\f"; break;
      case '\n': out += "\\n"; break;
      case '\r': out += "\\r"; break;
      case '\t': out += "\\t"; break;
      default:
        if (c < 0x20)
          out += fmt::format("\\u{:04x}", static_cast<unsigned>(c));
        else
          out += ch;  // UTF-8 multibyte sequences pass through unchanged
    }
  }
  out += '"';
  return out;
}

Json& Json::operator[](std::string_view key) {
  if (is_null()) value_ = Object{};
  auto* members = std::get_if<Object>(&value_);
  if (members == nullptr) throw std::logic_error("Json: operator[] on a value that is not an object");
  for (auto& [k, v] : *members)
    if (k == key) return v;
  members->emplace_back(std::string(key), Json());
  return members->back().second;
}

void Json::push_back(Json item) {
  if (is_null()) value_ = Array{};
  auto* items = std::get_if<Array>(&value_);
  if (items == nullptr) throw std::logic_error("Json: push_back on a value that is not an array");
  items->push_back(std::move(item));
}

std::string Json::dump(int indent) const {
  std::string out;
  dump_to(out, indent, 0);
  return out;
}

void Json::dump_to(std::string& out, int indent, int depth) const {
  const char* colon = indent < 0 ? ":" : ": ";
  struct Visitor {
    std::string& out;
    int indent, depth;
    const char* colon;
    void operator()(std::nullptr_t) const { out += "null"; }
    void operator()(bool b) const { out += b ? "true" : "false"; }
    void operator()(std::int64_t i) const { out += fmt::format("{}", i); }
    void operator()(double d) const { out += json_number(d); }
    void operator()(const std::string& s) const { out += json_string(s); }
    void operator()(const Array& items) const {
      out += '[';
      for (std::size_t i = 0; i < items.size(); ++i) {
        if (i > 0) out += ',';
        newline_and_indent(out, indent, depth + 1);
        items[i].dump_to(out, indent, depth + 1);
      }
      if (!items.empty()) newline_and_indent(out, indent, depth);
      out += ']';
    }
    void operator()(const Object& members) const {
      out += '{';
      for (std::size_t i = 0; i < members.size(); ++i) {
        if (i > 0) out += ',';
        newline_and_indent(out, indent, depth + 1);
        out += json_string(members[i].first);
        out += colon;
        members[i].second.dump_to(out, indent, depth + 1);
      }
      if (!members.empty()) newline_and_indent(out, indent, depth);
      out += '}';
    }
  };
  std::visit(Visitor{out, indent, depth, colon}, value_);
}

void write_json_file(const std::filesystem::path& path, const Json& value, int indent) {
  write_file_atomically(path, value.dump(indent) + "\n");
}

}  // namespace dsdem::io
