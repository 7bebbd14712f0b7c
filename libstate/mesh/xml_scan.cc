#include "mesh/xml_scan.h"

#include "mesh/text_cursor.h"
#include "util/error.h"

#include <algorithm>
#include <cctype>

namespace hapstate {
namespace {

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }
bool is_name_char(char c) {
  return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '_' || c == '-' || c == '.' ||
         c == ':';
}

std::string decode_entities(std::string_view v) {
  std::string out;
  for (std::size_t i = 0; i < v.size(); ++i) {
    if (v[i] != '&') {
      out += v[i];
      continue;
    }
    static const std::pair<std::string_view, char> kEntities[] = {
        {"&quot;", '"'}, {"&amp;", '&'}, {"&lt;", '<'}, {"&gt;", '>'}, {"&apos;", '\''}};
    bool done = false;
    for (const auto& [name, ch] : kEntities) {
      if (v.substr(i, name.size()) == name) {
        out += ch;
        i += name.size() - 1;
        done = true;
        break;
      }
    }
    if (!done) out += '&';
  }
  return out;
}

class Scanner {
 public:
  Scanner(std::string_view text, const std::string& source, XmlDocument* doc)
      : text_(text), source_(source), doc_(doc) {}

  [[noreturn]] void fail(std::size_t offset, const std::string& message) const {
    throw InputError(source_ + ":" + std::to_string(doc_->line_at(offset)) + ": " + message);
  }

  void run() {
    std::vector<XmlElement*> stack;
    std::vector<XmlElement> top;
    std::size_t pos = 0;
    while (true) {
      const std::size_t lt = text_.find('<', pos);
      const std::size_t text_end = lt == std::string_view::npos ? text_.size() : lt;
      add_text(stack, pos, text_end);
      if (lt == std::string_view::npos) break;
      pos = lt;
      if (text_.substr(pos, 4) == "<!--") {
        pos = skip_to(pos, "-->", "comment");
      } else if (text_.substr(pos, 9) == "<![CDATA[") {
        const std::size_t end = text_.find("]]>", pos);
        if (end == std::string_view::npos) fail(pos, "truncated file: unterminated CDATA section");
        add_text(stack, pos + 9, end);
        pos = end + 3;
      } else if (text_.substr(pos, 2) == "<?" || text_.substr(pos, 2) == "<!") {
        pos = skip_to(pos, text_[pos + 1] == '?' ? "?>" : ">", "declaration");
      } else if (text_.substr(pos, 2) == "</") {
        std::size_t p = pos + 2;
        const std::size_t name_begin = p;
        while (p < text_.size() && is_name_char(text_[p])) ++p;
        const std::string_view name = text_.substr(name_begin, p - name_begin);
        while (p < text_.size() && is_space(text_[p])) ++p;
        if (p >= text_.size() || text_[p] != '>')
          fail(pos, "truncated file: unterminated end tag </" + std::string(name));
        if (stack.empty()) fail(pos, "unexpected end tag </" + std::string(name) + ">");
        if (stack.back()->name != name) {
          fail(pos, "expected </" + stack.back()->name + ">, got </" + printable(name) + ">");
        }
        stack.pop_back();
        pos = p + 1;
      } else {
        XmlElement element;
        bool self_closing = false;
        pos = parse_start_tag(pos, &element, &self_closing);
        std::vector<XmlElement>& siblings = stack.empty() ? top : stack.back()->children;
        siblings.push_back(std::move(element));
        XmlElement* e = &siblings.back();
        if (!self_closing && e->name == "AppendedData") {
          pos = read_appended(pos, *e);
          continue;
        }
        if (!self_closing) stack.push_back(e);
      }
    }
    if (!stack.empty()) {
      fail(text_.size(), "truncated file: missing </" + stack.back()->name + "> (opened at line " +
                             std::to_string(doc_->line_at(stack.back()->offset)) + ")");
    }
    if (top.size() != 1)
      fail(0, "expected exactly one top-level XML element, found " + std::to_string(top.size()));
    doc_->root = std::move(top.front());
  }

 private:
  void add_text(const std::vector<XmlElement*>& stack, std::size_t begin, std::size_t end) {
    std::string_view t = text_.substr(begin, end - begin);
    std::size_t lead = 0;
    while (lead < t.size() && is_space(t[lead])) ++lead;
    if (lead == t.size()) return;
    if (stack.empty()) fail(begin + lead, "text outside of the XML root element");
    XmlElement& e = *stack.back();
    if (!e.text.empty())
      fail(begin + lead,
           "element <" + e.name + "> has text in several places (expected one block)");
    e.text = t;
    e.text_offset = begin;
  }

  std::size_t skip_to(std::size_t pos, std::string_view end, const char* what) {
    const std::size_t found = text_.find(end, pos);
    if (found == std::string_view::npos)
      fail(pos, std::string("truncated file: unterminated ") + what);
    return found + end.size();
  }

  std::size_t parse_start_tag(std::size_t pos, XmlElement* e, bool* self_closing) {
    e->offset = pos;
    std::size_t p = pos + 1;
    const std::size_t name_begin = p;
    while (p < text_.size() && is_name_char(text_[p])) ++p;
    if (p == name_begin) fail(pos, "expected an element name after '<'");
    e->name = std::string(text_.substr(name_begin, p - name_begin));
    while (true) {
      while (p < text_.size() && is_space(text_[p])) ++p;
      if (p >= text_.size()) fail(pos, "truncated file: unterminated start tag <" + e->name);
      if (text_[p] == '>') return p + 1;
      if (text_[p] == '/') {
        if (p + 1 >= text_.size() || text_[p + 1] != '>')
          fail(p, "expected '/>' in <" + e->name + ">");
        *self_closing = true;
        return p + 2;
      }
      const std::size_t key_begin = p;
      while (p < text_.size() && is_name_char(text_[p])) ++p;
      if (p == key_begin)
        fail(p, "expected an attribute name in <" + e->name + ">, got '" +
                    printable(text_.substr(p, 1)) + "'");
      const std::string key(text_.substr(key_begin, p - key_begin));
      while (p < text_.size() && is_space(text_[p])) ++p;
      if (p >= text_.size() || text_[p] != '=')
        fail(p, "expected '=' after attribute " + key + " in <" + e->name + ">");
      ++p;
      while (p < text_.size() && is_space(text_[p])) ++p;
      if (p >= text_.size() || (text_[p] != '"' && text_[p] != '\'')) {
        fail(p, "expected a quoted value for attribute " + key + " in <" + e->name + ">");
      }
      const char quote = text_[p];
      const std::size_t value_end = text_.find(quote, p + 1);
      if (value_end == std::string_view::npos)
        fail(p, "truncated file: unterminated attribute value of " + key);
      e->attributes.emplace_back(key, decode_entities(text_.substr(p + 1, value_end - p - 1)));
      p = value_end + 1;
    }
  }

  // Raw appended data: everything between '_' and the last "</AppendedData>".
  std::size_t read_appended(std::size_t pos, const XmlElement& e) {
    const std::string* encoding = e.attribute("encoding");
    doc_->appended_encoding = encoding != nullptr ? *encoding : "raw";
    std::size_t p = pos;
    while (p < text_.size() && is_space(text_[p])) ++p;
    if (p >= text_.size() || text_[p] != '_')
      fail(p, "expected '_' at the start of <AppendedData>");
    const std::size_t end = text_.rfind("</AppendedData>");
    if (end == std::string_view::npos || end < p)
      fail(pos, "truncated file: missing </AppendedData>");
    doc_->appended = text_.substr(p + 1, end - p - 1);
    doc_->appended_offset = p + 1;
    return end + std::string_view("</AppendedData>").size();
  }

  std::string_view text_;
  const std::string& source_;
  XmlDocument* doc_;
};

}  // namespace

const std::string* XmlElement::attribute(std::string_view key) const {
  for (const auto& [k, v] : attributes) {
    if (k == key) return &v;
  }
  return nullptr;
}

const XmlElement* XmlElement::child(std::string_view child_name) const {
  for (const XmlElement& c : children) {
    if (c.name == child_name) return &c;
  }
  return nullptr;
}

int XmlDocument::line_at(std::size_t offset) const {
  return 1 + static_cast<int>(std::lower_bound(newlines.begin(), newlines.end(), offset) -
                              newlines.begin());
}

XmlDocument parse_xml(std::string_view text, const std::string& source) {
  XmlDocument doc;
  for (std::size_t i = text.find('\n'); i != std::string_view::npos; i = text.find('\n', i + 1))
    doc.newlines.push_back(i);
  Scanner(text, source, &doc).run();
  return doc;
}

}  // namespace hapstate
