// A minimal XML scanner, enough for VTK XML files: elements, attributes, text, comments, the
// XML declaration, CDATA and a raw <AppendedData> block (arbitrary bytes after '_', which a
// general XML parser cannot read). Keeps byte offsets so errors can name file:line.
#pragma once

#include <cstddef>
#include <memory>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace hapstate {

struct XmlElement {
  std::string name;
  std::vector<std::pair<std::string, std::string>> attributes;
  std::vector<XmlElement> children;
  std::size_t offset = 0;  // byte offset of '<' in the file
  std::string_view text;   // the element's non-blank text content (empty if none)
  std::size_t text_offset = 0;

  // Value of attribute `key`, or null.
  const std::string* attribute(std::string_view key) const;
  // First child named `child_name`, or null.
  const XmlElement* child(std::string_view child_name) const;
};

struct XmlDocument {
  XmlElement root;            // the single top-level element
  std::string_view appended;  // bytes after '_' in <AppendedData>, if any
  std::size_t appended_offset = 0;
  std::string appended_encoding;      // "raw" or "base64" (attribute of <AppendedData>)
  std::vector<std::size_t> newlines;  // offsets of every '\n', for line numbers

  // 1-based line of byte `offset`.
  int line_at(std::size_t offset) const;
};

// Parses `text` (kept by reference: the result's views point into it). Throws InputError
// "source:line: ..." for malformed XML (unterminated tags, mismatched end tags, truncation).
XmlDocument parse_xml(std::string_view text, const std::string& source);

}  // namespace hapstate
