// The preview's web server: the page, its status, its image and its camera
// moves, over HTTP on 127.0.0.1 only, through CivetWeb (no file is served
// from disk). Bounded: a fixed pool of worker threads, a short queue of
// accepted connections, a size limit on each request and timeouts, so that
// abusive clients get errors and neither the render nor memory suffers.
#pragma once

#include "preview_state.h"

struct mg_context;
struct mg_connection;

namespace penumbra::preview {

class PreviewServer {
public:
    /// Listens on 127.0.0.1:port (0: a free port the system picks) and serves
    /// `state`, which must outlive the server. Throws pnb::Error(IoError)
    /// "--preview-port N: cannot listen on 127.0.0.1:N: REASON" when it cannot.
    PreviewServer(PreviewState& state, int port);
    /// Stops listening and waits for the requests in flight.
    ~PreviewServer();
    PreviewServer(const PreviewServer&) = delete;
    PreviewServer& operator=(const PreviewServer&) = delete;

    /// The port it listens on.
    int port() const { return port_; }

private:
    static int handle(mg_connection* connection, void* self);
    int respond(mg_connection* connection);

    PreviewState& state_;
    mg_context* context_ = nullptr;
    int port_ = 0;
};

}  // namespace penumbra::preview
