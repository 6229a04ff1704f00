// Misuse of engine::Expected (engine/core/expected.h): asking a failed result for its value, or a
// successful one for its error.
#include <gtest/gtest.h>

#include <string>

#include "engine/core/expected.h"

namespace engine {
namespace {

Expected<int> failed() { return makeError("scene.glb: accessor 3: out of range"); }

std::string messageOf(auto&& access) {
  try {
    access();
  } catch (const BadExpectedAccess& e) {
    return e.what();
  }
  return "(nothing thrown)";
}

// Tricky: the value of a failed result threw std::bad_variant_access, whose message says nothing
// of the error that went unhandled, on every one of value()'s three overloads and through * and
// ->; and error() of a successful Status read an empty optional (undefined behaviour, often an
// empty message). Each misuse must throw BadExpectedAccess, the value's naming the error.
TEST(ExpectedMisuse, ValueOfAnErrorNamesTheErrorAndErrorOfAValueThrows) {
  const std::string named = "Expected::value() on an error: scene.glb: accessor 3: out of range";
  Expected<int> result = failed();
  const Expected<int>& constResult = result;
  EXPECT_EQ(messageOf([&] { (void)result.value(); }), named);
  EXPECT_EQ(messageOf([&] { (void)constResult.value(); }), named);
  EXPECT_EQ(messageOf([&] { (void)failed().value(); }), named);
  EXPECT_EQ(messageOf([&] { (void)*result; }), named);

  const Expected<std::string> text = std::string("ok");
  EXPECT_EQ(text->size(), 2u);
  EXPECT_EQ(messageOf([&] { (void)text.error(); }), "Expected::error() on a result that holds a value");
  const Status fine;
  EXPECT_EQ(messageOf([&] { (void)fine.error(); }), "Expected::error() on a result that holds a value");
  const Status broken = makeError("disk full");
  EXPECT_EQ(broken.error().message, "disk full");
}

}  // namespace
}  // namespace engine
