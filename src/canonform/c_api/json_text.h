// SPDX-License-Identifier: GPL-3.0-or-later
// canonform C API: JSON text out, without a JSON library (the core-only build of the C API has
// none). Objects keep the order their keys are written in; strings are escaped, with invalid
// UTF-8 bytes replaced by U+FFFD; a double is written with 17 significant digits (it reads back
// as the same double) and always as a JSON number with a fraction or exponent, so that Python's
// json module gives a float for it; non-finite doubles are written as null (as nlohmann-json does).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace canonform::c_api {

/// `s` as a JSON string literal (quotes included).
std::string json_string(const std::string& s);
/// `x` as a JSON number (or null).
std::string json_number(double x);

/// Writes one JSON value; commas between items are added as values follow each other.
class JsonWriter {
public:
    JsonWriter& begin_object();
    JsonWriter& end_object();
    JsonWriter& begin_array();
    JsonWriter& end_array();
    JsonWriter& key(const std::string& k);
    JsonWriter& value(const std::string& s);
    JsonWriter& value(const char* s) { return value(std::string(s)); }
    JsonWriter& value(double x);
    JsonWriter& value(int x) { return integer(x); }
    JsonWriter& value(long x) { return integer(x); }
    JsonWriter& value(long long x) { return integer(x); }
    JsonWriter& value(bool b);
    JsonWriter& value(const std::vector<std::string>& list);
    JsonWriter& null();
    JsonWriter& integer(std::int64_t x);
    /// The text written so far.
    const std::string& text() const { return out_; }

private:
    void separate();
    std::string out_;
    bool first_ = true;  // no item yet in the innermost container
    bool after_key_ = false;
};

}  // namespace canonform::c_api
