// A harness for testing the corpus replay itself (ctest FuzzReplay.SelfTest*): an input that
// starts with "reject" throws a beamtrace::InputError (an expected rejection), one that starts
// with "throw" a std::logic_error (which must fail the replay), anything else is accepted.
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>

#include "../fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string text = beamtrace::fuzz::as_text(data, size);
    return beamtrace::fuzz::run_guarded([&] {
        if (text.rfind("reject", 0) == 0) {
            throw beamtrace::InputError("selftest", "rejected");
        }
        if (text.rfind("throw", 0) == 0) {
            throw std::logic_error("an exception that is no beamtrace::Error");
        }
    });
}
