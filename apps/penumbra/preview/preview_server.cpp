#include "preview_server.h"

#include <arpa/inet.h>
#include <civetweb.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <nlohmann/json.hpp>
#include <string_view>

#include "orbit_camera.h"
#include "preview_page.h"

namespace penumbra::preview {
namespace {

// Requests are tiny (the page's polls and camera moves), so small bounds cost
// nothing: what a flood of requests can hold is threads x request size.
constexpr const char* kWorkerThreads = "4";
constexpr const char* kQueuedConnections = "16";  // accepted, waiting for a worker
constexpr const char* kMaxRequestHead = "8192";   // request line and headers, bytes
constexpr const char* kRequestTimeoutMs = "2000";
constexpr long long kMaxBody = 4096;

// The page's paths are plain ASCII: nothing is %-decoded, so an encoded byte
// (a NUL that would end the path early, an encoded dot) never joins a path.
constexpr const char* kDecodeUrl = "no";

// Each poll is a new connection: a thread-per-connection server keeps a
// worker per idle keep-alive connection, and browsers keep several open.
constexpr const char* kKeepAlive = "no";

// Every response: never cached, never sniffed as another type, never framed.
constexpr const char* kCommonHeaders =
    "Cache-Control: no-store\r\nX-Content-Type-Options: nosniff\r\nReferrer-Policy: no-referrer\r\n"
    "X-Frame-Options: DENY\r\n";

// The page is inline HTML, style and script; it talks to this server only.
constexpr const char* kPagePolicy =
    "default-src 'none'; img-src 'self' blob:; style-src 'unsafe-inline'; script-src 'unsafe-inline'; "
    "connect-src 'self'; frame-ancestors 'none'; base-uri 'none'; form-action 'none'";

int send(mg_connection* c, int status, const char* type, std::string_view body, const char* extra = "") {
    mg_response_header_start(c, status);
    mg_response_header_add(c, "Content-Type", type, -1);
    mg_response_header_add(c, "Content-Length", std::to_string(body.size()).c_str(), -1);
    mg_response_header_add_lines(c, kCommonHeaders);
    if (*extra) mg_response_header_add_lines(c, extra);
    mg_response_header_send(c);
    if (std::strcmp(mg_get_request_info(c)->request_method, "HEAD") != 0) mg_write(c, body.data(), body.size());
    return status;
}

int sendError(mg_connection* c, int status, const std::string& message, const char* extra = "") {
    return send(c, status, "text/plain; charset=utf-8", message + "\n", extra);
}

// Only names of this machine's loopback at this port: a page elsewhere that
// resolves its own name to 127.0.0.1 (DNS rebinding) is refused.
bool hostIsLoopback(mg_connection* c, int port) {
    const char* host = mg_get_header(c, "Host");
    if (!host) return false;
    const std::string_view h(host);
    const size_t colon = h.rfind(':');
    if (colon == std::string_view::npos || h.substr(colon + 1) != std::to_string(port)) return false;
    const std::string_view name = h.substr(0, colon);
    return name == "127.0.0.1" || name == "localhost";
}

// The request body, at most kMaxBody bytes, or the status that refuses it.
int readBody(mg_connection* c, std::string& body) {
    const long long length = mg_get_request_info(c)->content_length;
    if (length < 0) return 411;
    if (length > kMaxBody) return 413;
    body.resize(size_t(length));
    size_t got = 0;
    while (got < body.size()) {
        const int n = mg_read(c, body.data() + got, body.size() - got);
        if (n <= 0) return 400;
        got += size_t(n);
    }
    return 0;
}

double number(const nlohmann::json& v, const char* what, double limit) {
    if (!v.is_number()) throw std::invalid_argument(std::string(what) + " must be a number");
    const double x = v.get<double>();
    if (!std::isfinite(x) || std::fabs(x) > limit)
        throw std::invalid_argument(std::string(what) + " must be finite, at most " + std::to_string(int(limit)) +
                                    " in magnitude");
    return x;
}

std::pair<double, double> pair(const nlohmann::json& v, const char* what, double limit) {
    if (!v.is_array() || v.size() != 2) throw std::invalid_argument(std::string(what) + " must be [x, y]");
    return {number(v[0], what, limit), number(v[1], what, limit)};
}

// A camera move as the page sends it: {"orbit": [yaw, pitch]} in degrees,
// {"zoom": factor}, {"pan": [right, up]} in view heights, or {"reset": true}.
void applyMove(PreviewState& state, const nlohmann::json& move) {
    if (!move.is_object() || move.size() != 1)
        throw std::invalid_argument("expected one of {\"orbit\": [yaw, pitch]}, {\"zoom\": f}, {\"pan\": [x, y]}, "
                                    "{\"reset\": true}");
    // (Not a structured binding of *move.items().begin(): that proxy is a
    // temporary, gone before its key is read.)
    const auto first = move.begin();
    const std::string key = first.key();
    const nlohmann::json& value = first.value();
    if (key == "orbit") {
        const auto [yaw, pitch] = pair(value, "orbit", 360.0);
        state.moveCamera([&](const pnb::Camera& c) { return orbit(c, yaw, pitch); });
    } else if (key == "zoom") {
        const double f = number(value, "zoom", 100.0);
        if (f < 0.01) throw std::invalid_argument("zoom must lie in [0.01, 100]");
        state.moveCamera([&](const pnb::Camera& c) { return zoom(c, f); });
    } else if (key == "pan") {
        const auto [x, y] = pair(value, "pan", 100.0);
        state.moveCamera([&](const pnb::Camera& c) { return pan(c, x, y); });
    } else if (key == "reset" && value == true) {
        state.resetCamera();
    } else {
        throw std::invalid_argument("unknown camera move '" + key + "'");
    }
}

int moveCamera(mg_connection* c, PreviewState& state) {
    const char* type = mg_get_header(c, "Content-Type");
    // JSON only: a cross-site form or a "simple" request cannot send it without the browser asking first.
    if (!type || std::string_view(type).substr(0, 16) != "application/json")
        return sendError(c, 415, "camera moves are application/json");
    std::string body;
    if (const int refused = readBody(c, body)) {
        const char* why = refused == 411 ? "a camera move needs a Content-Length"
                          : refused == 413 ? "a camera move is at most 4096 bytes"
                                           : "the request body ended early";
        return sendError(c, refused, why);
    }
    const nlohmann::json move = nlohmann::json::parse(body, nullptr, false);
    if (move.is_discarded()) return sendError(c, 400, "a camera move is JSON");
    try {
        applyMove(state, move);
    } catch (const std::invalid_argument& e) {
        return sendError(c, 400, std::string("camera: ") + e.what());
    } catch (const pnb::Error& e) {
        return sendError(c, e.code() == pnb::ErrorCode::InvalidScene ? 409 : 400, std::string("camera: ") + e.what());
    }
    return send(c, 200, "application/json", state.statusJson());
}

int sendImage(mg_connection* c, PreviewState& state) {
    const std::optional<PreviewState::Image> image = state.image();
    if (!image) return sendError(c, 503, "no image yet: the first pass is rendering", "Retry-After: 1\r\n");
    // Which pass and which view the image shows: the page keeps the newest.
    const std::string headers = "X-Penumbra-Version: " + std::to_string(image->version) +
                                "\r\nX-Penumbra-View: " + std::to_string(image->view) + "\r\n";
    const auto* bytes = reinterpret_cast<const char*>(image->bytes->data());
    return send(c, 200, image->type, std::string_view(bytes, image->bytes->size()), headers.c_str());
}

// CivetWeb would print its messages; the command says what went wrong itself.
int quiet(const mg_connection*, const char*) { return 1; }

// Why 127.0.0.1:port cannot be bound, asked of the system directly (CivetWeb
// says only that it failed); `fallback` when the port binds now.
std::string bindProblem(int port, const std::string& fallback) {
    const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    if (fd < 0) return std::strerror(errno);
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_port = htons(std::uint16_t(port));
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    const bool bound = ::bind(fd, reinterpret_cast<const sockaddr*>(&address), sizeof address) == 0;
    const std::string why = bound ? fallback : std::strerror(errno);
    ::close(fd);
    return why;
}

}  // namespace

PreviewServer::PreviewServer(PreviewState& state, int port) : state_(state) {
    mg_init_library(0);
    const std::string address = "127.0.0.1:" + std::to_string(port);
    const char* options[] = {"listening_ports", address.c_str(), "num_threads", kWorkerThreads,
                             "connection_queue", kQueuedConnections, "listen_backlog", kQueuedConnections,
                             "max_request_size", kMaxRequestHead, "request_timeout_ms", kRequestTimeoutMs,
                             "enable_keep_alive", kKeepAlive, "decode_url", kDecodeUrl, nullptr};
    mg_callbacks callbacks{};
    callbacks.log_message = quiet;
    mg_init_data init{};
    init.callbacks = &callbacks;
    init.configuration_options = options;
    char text[256] = "";
    mg_error_data error{};
    error.text = text;
    error.text_buffer_size = sizeof text;
    context_ = mg_start2(&init, &error);
    if (!context_) {
        mg_exit_library();
        throw pnb::Error(pnb::ErrorCode::IoError, "--preview-port " + std::to_string(port) + ": cannot listen on " +
                                                      address + ": " + bindProblem(port, text));
    }
    mg_server_port ports[1];
    port_ = mg_get_server_ports(context_, 1, ports) == 1 ? ports[0].port : port;
    // One handler for every path: it serves the page's own resources and refuses the rest.
    mg_set_request_handler(context_, "/", &PreviewServer::handle, this);
}

PreviewServer::~PreviewServer() {
    mg_stop(context_);
    mg_exit_library();
}

int PreviewServer::handle(mg_connection* connection, void* self) {
    try {
        return static_cast<PreviewServer*>(self)->respond(connection);
    } catch (const std::exception& e) {
        return sendError(connection, 500, e.what());  // an encoder failure, out of memory: this request only
    }
}

int PreviewServer::respond(mg_connection* c) {
    const mg_request_info* request = mg_get_request_info(c);
    if (!hostIsLoopback(c, port_)) return sendError(c, 403, "this server answers to 127.0.0.1 and localhost only");
    const std::string_view path(request->local_uri ? request->local_uri : "");
    const std::string_view method(request->request_method);
    const bool get = method == "GET" || method == "HEAD";
    if (path == "/")
        return get ? send(c, 200, "text/html; charset=utf-8", kPreviewPage,
                          ("Content-Security-Policy: " + std::string(kPagePolicy) + "\r\n").c_str())
                   : sendError(c, 405, "GET only", "Allow: GET, HEAD\r\n");
    if (path == "/status")
        return get ? send(c, 200, "application/json", state_.statusJson())
                   : sendError(c, 405, "GET only", "Allow: GET, HEAD\r\n");
    if (path == "/image") return get ? sendImage(c, state_) : sendError(c, 405, "GET only", "Allow: GET, HEAD\r\n");
    if (path == "/camera")
        return method == "POST" ? moveCamera(c, state_) : sendError(c, 405, "POST only", "Allow: POST\r\n");
    return sendError(c, 404, "not found");
}

}  // namespace penumbra::preview
