#include "sf/web/testing/client.hpp"

#include <boost/asio/ssl/host_name_verification.hpp>
#include <boost/beast/ssl.hpp>

namespace sf::web::testing {
namespace net = boost::asio;
namespace beast = boost::beast;
using tcp = net::ip::tcp;

tcp::socket connect(net::io_context& context, std::uint16_t port, int receive_buffer) {
  tcp::socket socket(context);
  socket.open(tcp::v4());
  if (receive_buffer > 0) {
    socket.set_option(net::socket_base::receive_buffer_size(receive_buffer));
  }
  socket.connect(tcp::endpoint(net::ip::make_address("127.0.0.1"), port));
  return socket;
}

namespace {

// One request and its response on a connected stream, plain or TLS.
template <typename Stream>
HttpResponse exchange(Stream& stream, http::verb method, std::string_view target, std::string body,
                      std::string_view content_type, const HeaderList& headers) {
  http::request<http::string_body> request{method, beast::string_view(target.data(), target.size()), 11};
  request.set(http::field::host, "127.0.0.1");
  for (const auto& [name, value] : headers) {
    request.set(name, value);
  }
  if (!body.empty()) {
    request.set(http::field::content_type, beast::string_view(content_type.data(), content_type.size()));
    request.body() = std::move(body);
  }
  request.prepare_payload();
  beast::error_code ignored;
  http::write(stream, request, ignored);  // a refused body may be cut short; the answer is read
  beast::flat_buffer buffer;
  http::response_parser<http::string_body> parser;
  parser.body_limit(64ULL * 1024ULL * 1024ULL);
  parser.skip(method == http::verb::head);
  http::read(stream, buffer, parser);
  return parser.release();
}

}  // namespace

HttpResponse http_request(std::uint16_t port, http::verb method, std::string_view target, std::string body,
                          std::string_view content_type, const HeaderList& headers) {
  net::io_context context;
  auto socket = connect(context, port);
  return exchange(socket, method, target, std::move(body), content_type, headers);
}

HttpResponse https_request(const std::filesystem::path& ca, std::uint16_t port, http::verb method,
                           std::string_view target, std::string body, std::string_view content_type,
                           const HeaderList& headers) {
  net::io_context context;
  net::ssl::context tls(net::ssl::context::tls_client);
  tls.load_verify_file(ca.string());
  tls.set_verify_mode(net::ssl::verify_peer);
  beast::ssl_stream<tcp::socket> stream(connect(context, port), tls);
  stream.set_verify_callback(net::ssl::host_name_verification("127.0.0.1"));
  stream.handshake(net::ssl::stream_base::client);
  return exchange(stream, method, target, std::move(body), content_type, headers);
}

std::string raw_exchange(std::uint16_t port, std::string_view bytes) {
  net::io_context context;
  auto socket = connect(context, port);
  beast::error_code error;
  net::write(socket, net::buffer(bytes.data(), bytes.size()), error);
  socket.shutdown(tcp::socket::shutdown_send, error);
  std::string out;
  char chunk[4096];
  while (true) {
    const auto n = socket.read_some(net::buffer(chunk), error);
    out.append(chunk, n);
    if (error) {
      return out;
    }
  }
}

int raw_status(std::string_view response) {
  if (response.size() < 12 || response.substr(0, 9) != "HTTP/1.1 ") {
    return 0;
  }
  return std::stoi(std::string(response.substr(9, 3)));
}

int write_and_read_status(tcp::socket& socket, beast::flat_buffer& buffer, std::string_view bytes) {
  net::write(socket, net::buffer(bytes.data(), bytes.size()));
  http::response<http::empty_body> response;
  http::read(socket, buffer, response);
  return static_cast<int>(response.result_int());
}

LiveClient::LiveClient(std::uint16_t port, int receive_buffer, const std::string& cookie)
    : ws_(connect(context_, port, receive_buffer)) {
  if (!cookie.empty()) {
    ws_.set_option(
        beast::websocket::stream_base::decorator([cookie](beast::websocket::request_type& request) {
          request.set(beast::http::field::cookie, cookie);
        }));
  }
  ws_.handshake("127.0.0.1", "/api/live");
}

void LiveClient::send(std::string_view text) {
  ws_.text(true);
  ws_.write(net::buffer(text.data(), text.size()));
}

void LiveClient::send_binary(std::string_view bytes) {
  ws_.binary(true);
  ws_.write(net::buffer(bytes.data(), bytes.size()));
}

nlohmann::json LiveClient::receive() {
  beast::flat_buffer buffer;
  ws_.read(buffer);
  return nlohmann::json::parse(beast::buffers_to_string(buffer.data()));
}

int LiveClient::close_code() {
  beast::flat_buffer buffer;
  beast::error_code error;
  while (!error) {
    buffer.consume(buffer.size());
    ws_.read(buffer, error);
  }
  return error == beast::websocket::error::closed ? static_cast<int>(ws_.reason().code) : 0;
}

}  // namespace sf::web::testing
