#include "xml_elements.hpp"

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <cstring>

#include "stvd/errors.hpp"

namespace stvd::surface_io::detail {
namespace {

constexpr int kMaxDepth = 64;

class Parser {
 public:
  Parser(const std::string& text, const std::string& path) : s_(text), path_(path) {}

  XmlElement document() {
    skipMisc();
    if (!startsWith("<")) fail("no root element");
    XmlElement root = element(0);
    skipMisc();
    if (i_ != s_.size()) fail("content after the root element");
    return root;
  }

 private:
  const std::string& s_;
  const std::string& path_;
  std::size_t i_ = 0;
  // Lines counted up to `counted_`: the parser only moves forward, so each
  // byte is counted once (counting from the start at every element made
  // a 4 MB surface's few elements cost as much as its data).
  std::size_t counted_ = 0, line_ = 1;

  std::size_t lineAt(std::size_t position) {
    position = std::min(position, s_.size());
    if (position < counted_) {
      counted_ = 0;
      line_ = 1;
    }
    line_ += static_cast<std::size_t>(std::count(s_.begin() + counted_, s_.begin() + position, '\n'));
    counted_ = position;
    return line_;
  }
  [[noreturn]] void fail(const std::string& problem) {
    throw MeshFileError(path_ + ": line " + std::to_string(lineAt(i_)) + ": XML: " + problem);
  }
  bool startsWith(const char* t) const { return s_.compare(i_, std::strlen(t), t) == 0; }
  static bool space(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }
  static bool nameChar(char c) {
    const unsigned char u = static_cast<unsigned char>(c);
    return std::isalnum(u) || c == '_' || c == ':' || c == '-' || c == '.' || u >= 0x80;
  }
  void skipSpace() {
    while (i_ < s_.size() && space(s_[i_])) ++i_;
  }
  /// Moves past `end`, or fails naming `what`.
  void skipPast(const char* end, const char* what) {
    const std::size_t at = s_.find(end, i_);
    if (at == std::string::npos) fail(std::string("unterminated ") + what);
    i_ = at + std::strlen(end);
  }
  /// Comments, processing instructions, the XML declaration, a DOCTYPE
  /// (with an internal subset in brackets) and white space.
  void skipMisc() {
    for (;;) {
      skipSpace();
      if (startsWith("<?")) skipPast("?>", "processing instruction");
      else if (startsWith("<!--")) skipPast("-->", "comment");
      else if (startsWith("<!DOCTYPE")) skipDoctype();
      else return;
    }
  }
  void skipDoctype() {
    int brackets = 0;
    for (; i_ < s_.size(); ++i_) {
      const char c = s_[i_];
      if (c == '[') ++brackets;
      else if (c == ']') --brackets;
      else if (c == '>' && brackets <= 0) {
        ++i_;
        return;
      }
    }
    fail("unterminated DOCTYPE");
  }
  std::string name() {
    const std::size_t start = i_;
    while (i_ < s_.size() && nameChar(s_[i_])) ++i_;
    if (i_ == start) fail("expected a name");
    return s_.substr(start, i_ - start);
  }
  static void appendUtf8(std::string& out, std::uint32_t c) {
    if (c < 0x80) {
      out += static_cast<char>(c);
    } else if (c < 0x800) {
      out += static_cast<char>(0xC0 | (c >> 6));
      out += static_cast<char>(0x80 | (c & 0x3F));
    } else if (c < 0x10000) {
      out += static_cast<char>(0xE0 | (c >> 12));
      out += static_cast<char>(0x80 | ((c >> 6) & 0x3F));
      out += static_cast<char>(0x80 | (c & 0x3F));
    } else {
      out += static_cast<char>(0xF0 | (c >> 18));
      out += static_cast<char>(0x80 | ((c >> 12) & 0x3F));
      out += static_cast<char>(0x80 | ((c >> 6) & 0x3F));
      out += static_cast<char>(0x80 | (c & 0x3F));
    }
  }
  /// At '&': appends the entity's character.
  void entity(std::string& out) {
    const std::size_t end = s_.find(';', i_);
    if (end == std::string::npos || end - i_ > 12) fail("unterminated entity reference");
    const std::string e = s_.substr(i_ + 1, end - i_ - 1);
    i_ = end + 1;
    if (e == "lt") out += '<';
    else if (e == "gt") out += '>';
    else if (e == "amp") out += '&';
    else if (e == "quot") out += '"';
    else if (e == "apos") out += '\'';
    else if (e.size() > 1 && e[0] == '#') {
      const bool hex = e[1] == 'x' || e[1] == 'X';
      const std::string digits = e.substr(hex ? 2 : 1);
      if (digits.empty() || digits.size() > 8 ||
          digits.find_first_not_of(hex ? "0123456789abcdefABCDEF" : "0123456789") != std::string::npos)
        fail("bad character reference &" + e + ";");
      const unsigned long c = std::stoul(digits, nullptr, hex ? 16 : 10);
      if (c == 0 || c > 0x10FFFF) fail("bad character reference &" + e + ";");
      appendUtf8(out, static_cast<std::uint32_t>(c));
    } else {
      fail("unknown entity &" + e + "; (only XML's own five and character references are read)");
    }
  }
  std::string attributeValue() {
    if (i_ >= s_.size() || (s_[i_] != '"' && s_[i_] != '\'')) fail("expected a quoted attribute value");
    const char quote = s_[i_++];
    std::string value;
    while (i_ < s_.size() && s_[i_] != quote) {
      if (s_[i_] == '<') fail("'<' in an attribute value");
      if (s_[i_] == '&') entity(value);
      else value += s_[i_++];
    }
    if (i_ >= s_.size()) fail("unterminated attribute value");
    ++i_;
    return value;
  }
  XmlElement element(int depth) {
    if (depth >= kMaxDepth) fail("elements nested deeper than " + std::to_string(kMaxDepth) + " levels");
    XmlElement e;
    e.line = lineAt(i_);
    ++i_;  // '<'
    e.name = name();
    for (;;) {
      skipSpace();
      if (i_ >= s_.size()) fail("unterminated start tag <" + e.name + ">");
      if (startsWith("/>")) {
        i_ += 2;
        return e;
      }
      if (s_[i_] == '>') {
        ++i_;
        break;
      }
      std::string key = name();
      skipSpace();
      if (i_ >= s_.size() || s_[i_] != '=') fail("expected '=' after attribute " + key);
      ++i_;
      skipSpace();
      e.attributes.emplace_back(std::move(key), attributeValue());
    }
    for (;;) {
      if (i_ >= s_.size()) fail("element <" + e.name + "> is not closed");
      const char c = s_[i_];
      if (c == '&') {
        entity(e.text);
      } else if (c != '<') {
        // Character data up to the next markup or entity (a plain loop: a
        // surface's arrays are megabytes of it).
        std::size_t end = i_;
        while (end < s_.size() && s_[end] != '<' && s_[end] != '&') ++end;
        e.text.append(s_, i_, end - i_);
        i_ = end;
      } else if (startsWith("<![CDATA[")) {
        const std::size_t start = i_ + 9;
        skipPast("]]>", "CDATA section");
        e.text.append(s_, start, i_ - 3 - start);
      } else if (startsWith("<!--")) {
        skipPast("-->", "comment");
      } else if (startsWith("<?")) {
        skipPast("?>", "processing instruction");
      } else if (startsWith("</")) {
        i_ += 2;
        const std::string closing = name();
        if (closing != e.name) fail("</" + closing + "> closes <" + e.name + ">");
        skipSpace();
        if (i_ >= s_.size() || s_[i_] != '>') fail("expected '>' after </" + closing);
        ++i_;
        return e;
      } else if (startsWith("<!")) {
        fail("unexpected markup declaration inside <" + e.name + ">");
      } else {
        e.children.push_back(element(depth + 1));
      }
    }
  }
};

}  // namespace

const std::string* XmlElement::attribute(const std::string& key) const {
  for (const auto& [k, v] : attributes)
    if (k == key) return &v;
  return nullptr;
}

const XmlElement* XmlElement::child(const std::string& childName) const {
  for (const XmlElement& c : children)
    if (c.name == childName) return &c;
  return nullptr;
}

XmlElement parseXml(const std::string& text, const std::string& path) { return Parser(text, path).document(); }

}  // namespace stvd::surface_io::detail
