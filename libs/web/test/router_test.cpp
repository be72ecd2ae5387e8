#include "sf/web/router.hpp"

#include <gtest/gtest.h>

#include <stdexcept>

namespace sf::web {
namespace {

Request request(std::string method, std::string path) {
  Request r;
  r.method = std::move(method);
  r.path = std::move(path);
  return r;
}

Router orders_router() {
  Router router;
  EXPECT_TRUE(router.add("GET", "/api/orders", [](const Request&) {
    return json_response({{"list", true}});
  }));
  EXPECT_TRUE(router.add("GET", "/api/orders/{id}", [](const Request& r) {
    return json_response({{"id", r.path_params.at("id")}});
  }));
  EXPECT_TRUE(
      router.add("DELETE", "/api/orders/{id}", [](const Request&) { return json_response({}, 204); }));
  EXPECT_TRUE(router.add("GET", "/api/orders/{id}/log/{step}", [](const Request& r) {
    return json_response({{"id", r.path_params.at("id")}, {"step", r.path_params.at("step")}});
  }));
  return router;
}

TEST(Router, MatchesLiteralAndParameterSegments) {
  const auto router = orders_router();
  auto list = request("GET", "/api/orders");
  EXPECT_EQ(router.dispatch(list)->body, R"({"list":true})");
  auto one = request("GET", "/api/orders/42");
  EXPECT_EQ(router.dispatch(one)->body, R"({"id":"42"})");
  auto step = request("GET", "/api/orders/7/log/award");
  EXPECT_EQ(router.dispatch(step)->body, R"({"id":"7","step":"award"})");
}

TEST(Router, NoPatternMatchLeavesTheRequestToTheCaller) {
  const auto router = orders_router();
  for (const char* path : {"/api/order", "/api/orders/", "/api/orders/1/2", "/", "/api/orders/1/log"}) {
    auto r = request("GET", path);
    EXPECT_FALSE(router.dispatch(r).has_value()) << path;
  }
}

TEST(Router, OtherMethodIs405WithAllow) {
  const auto router = orders_router();
  auto r = request("PUT", "/api/orders/9");
  auto response = router.dispatch(r);
  ASSERT_TRUE(response);
  EXPECT_EQ(response->status, 405);
  EXPECT_EQ(response->headers.get("allow"), "DELETE, GET");
  EXPECT_EQ(nlohmann::json::parse(response->body).at("status"), 405);
}

TEST(Router, ThrowingHandlerIs500WithoutItsMessage) {
  Router router;
  ASSERT_TRUE(
      router.add("GET", "/boom", [](const Request&) -> Response { throw std::runtime_error("secret"); }));
  auto r = request("GET", "/boom");
  auto response = router.dispatch(r);
  ASSERT_TRUE(response);
  EXPECT_EQ(response->status, 500);
  EXPECT_EQ(response->body.find("secret"), std::string::npos);
  EXPECT_TRUE(nlohmann::json::parse(response->body).contains("error"));
}

TEST(Router, RefusesBadPatterns) {
  Router router;
  const Handler ok = [](const Request&) { return Response{}; };
  EXPECT_FALSE(router.add("GET", "api/x", ok));
  EXPECT_FALSE(router.add("GET", "/api/x{id}", ok));
  EXPECT_FALSE(router.add("", "/api", ok));
  EXPECT_FALSE(router.add("GET", "/api", nullptr));
}

TEST(Message, JsonBodyReportsWhereItIsMalformed) {
  Request r;
  r.body = R"({"box": )";
  auto body = json_body(r);
  ASSERT_FALSE(body);
  EXPECT_NE(body.error().message.find("not JSON"), std::string::npos);
  r.body = R"({"box": "A"})";
  EXPECT_EQ(json_body(r)->at("box"), "A");
}

TEST(Message, FieldNamesCompareCaseInsensitively) {
  Fields fields;
  fields.add("Content-Type", "a");
  fields.set("content-type", "b");
  EXPECT_EQ(fields.get("CONTENT-TYPE"), "b");
  EXPECT_EQ(fields.all().size(), 1U);
  EXPECT_FALSE(fields.get("Accept"));
}

}  // namespace
}  // namespace sf::web
