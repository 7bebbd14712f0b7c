// Test helper: expects a callable to throw hapstate::InputError whose message contains given parts.
#pragma once

#include "util/error.h"

#include <gtest/gtest.h>

#include <initializer_list>
#include <string>

namespace hapstate::test_util {

// Expects `f` to throw InputError whose message contains every one of `parts`.
template <class F>
void expect_input_error(F&& f, std::initializer_list<std::string> parts) {
  try {
    f();
    ADD_FAILURE() << "no InputError thrown";
  } catch (const InputError& e) {
    const std::string message = e.what();
    for (const auto& part : parts) EXPECT_NE(message.find(part), std::string::npos) << message;
  }
}

// Expects `f` to throw InputError whose message contains `part`.
template <class F>
void expect_input_error(F&& f, const std::string& part) {
  expect_input_error(std::forward<F>(f), {part});
}

}  // namespace hapstate::test_util
