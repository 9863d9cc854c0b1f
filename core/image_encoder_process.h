// A helper process that loads the image module (OpenImageIO and its ~260
// shared libraries: about 0.1 s of CPU loaded deepest first, 0.17 s in one
// dlopen; most of a sub-second render's overhead) while the parent renders, then encodes the parent's images into
// memory. Loading the libraries on a thread of the rendering process was
// measured slower: every mapping a loader makes in a process with running
// threads interrupts them all (TLB shootdowns), and the system time grew
// several times over; a separate process has its own address space. The
// parent still writes every file itself (core/atomic_file.h), so what a
// failed or interrupted write leaves is as without the helper; if the helper
// cannot answer (it died, the socket broke), the caller encodes in-process.
#pragma once

#include <sys/types.h>

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/oiio/oiio_api.h"

namespace penumbra {

class ImageEncoderProcess {
public:
    /// Forks the helper, which starts loading the module at once. Call it
    /// while the process has one thread (the child of a multi-threaded fork
    /// may find a lock held forever). nullptr where the process cannot be
    /// started: then encode in-process.
    static std::unique_ptr<ImageEncoderProcess> start();
    /// Ends the helper (killed: it holds nothing but memory) and reaps it.
    ~ImageEncoderProcess();
    ImageEncoderProcess(const ImageEncoderProcess&) = delete;
    ImageEncoderProcess& operator=(const ImageEncoderProcess&) = delete;

    /// oiio::Api::encode in the helper: true with the encoded bytes in `out`,
    /// or false with the module's message in `error` (also where the helper
    /// could not load the module: the message the in-process load gives).
    /// nullopt where the helper gave no answer (it is not asked again) or
    /// the image is over 256 MiB of pixels (not copied to the helper: encode
    /// it in-process). One call at a time.
    std::optional<bool> encode(const oiio::EncodeRequest& request, std::vector<unsigned char>& out,
                               std::string& error);

    /// The helper's process id (for tests that end it early).
    pid_t pid() const { return pid_; }

private:
    ImageEncoderProcess(int fd, pid_t pid) : fd_(fd), pid_(pid) {}
    void stop();

    int fd_ = -1;  // the parent's end of the socket pair; -1 once the helper is gone
    pid_t pid_ = -1;
};

}  // namespace penumbra
