#pragma once
// Will a stereo/frame sample cross the transport? Cyclone sends a large best-effort sample as a
// burst of datagrams that the reader's socket receive buffer must hold at once; a sample larger
// than that buffer mostly never arrives, and nothing else says so. The buffer is what Cyclone
// asks for (SocketReceiveBufferSize in the configuration in force, CYCLONEDDS_URI) capped by the
// kernel at net.core.rmem_max. Frame publishers (camera_server) and readers (ball_detector)
// check their samples against it and name the remedies.

#include <cstdint>
#include <functional>
#include <optional>
#include <string>

namespace stereoball::stereo {

/// Cyclone's request when its configuration sets no SocketReceiveBufferSize (Cyclone 0.10's
/// built-in minimum of 1 MiB; an assumption, documented in components/stereo/README.md).
inline constexpr uint64_t kCycloneDefaultReceiveBufferBytes = 1u << 20;

/// The socket receive buffer a reader of this process gets.
struct TransportLimits {
  uint64_t requested_bytes = kCycloneDefaultReceiveBufferBytes;  ///< Cyclone's request
  std::string requested_from = "Cyclone's default";              ///< where the request comes from
  uint64_t rmem_max_bytes = 0;                                   ///< net.core.rmem_max; 0 = unknown
  bool shared_memory = false;                                    ///< iceoryx carries local samples
  bool keyless = false;  ///< the built-in loopback-only configuration is in force

  /// The buffer granted: the request capped at rmem_max (the request when the cap is unknown).
  uint64_t receive_buffer_bytes() const;
  /// The largest sample that arrives whole: Linux doubles the granted value for its own
  /// bookkeeping and a 64 KB loopback datagram costs about its size, so twice the buffer.
  /// Measured on loopback with a 4 MiB buffer (camera_server, 2 Hz, one idle reader): 7.0 MB
  /// samples 40 of 40 arrived, 8.6 MB 17 of 40, 10.5 MB 9 of 40. Over a LAN the 1500-byte IP
  /// fragments cost more memory each, so losses may start below this.
  uint64_t capacity_bytes() const { return 2 * receive_buffer_bytes(); }
};

/// Bytes of a Cyclone size value ("16MB", "1MiB", "64kB", "65500B", "4194304"; Cyclone's units
/// are binary: kB = KiB = 1024 B); nullopt for "default", a ${VAR} or anything unparsable.
std::optional<uint64_t> parse_cyclone_size(const std::string& text);

/// The SocketReceiveBufferSize request of a CYCLONEDDS_URI value (comma-separated file:// paths,
/// plain paths or inline XML; a later entry overrides an earlier one): the max attribute, else
/// the min attribute; nullopt when none sets one. read_file returns a file's text.
std::optional<std::pair<uint64_t, std::string>> configured_receive_buffer(
    const std::string& uri,
    const std::function<std::optional<std::string>(const std::string&)>& read_file);

/// The Cyclone configuration a process runs under: CYCLONEDDS_URI, or a built-in one that
/// replaces it (a process without a deployment key runs loopback only, whatever the variable
/// says; dds::keyless_cyclone_config()).
struct CycloneSetup {
  bool shared_memory = false;  ///< iceoryx carries local samples (never with a built-in config)
  std::string built_in_xml;    ///< the configuration in force when not empty
};

/// The limits in force for this process: its configuration and /proc/sys/net/core/rmem_max.
TransportLimits read_transport_limits(const CycloneSetup& setup);

/// Serialized size of a stereo/frame sample with eyes of these pixel byte counts (the pixels
/// plus the fixed fields and strings, rounded up).
uint64_t frame_sample_bytes(uint64_t left_bytes, uint64_t right_bytes);

/// The remedies for frames that do not cross the transport, one sentence ("Remedies: ...");
/// sample_bytes sizes the net.core.rmem_max to ask for; keyless: the process runs on the built-in
/// loopback-only configuration, so shared memory and a configuration file need a deployment key.
std::string transport_remedies(uint64_t sample_bytes, bool keyless = false);

/// One line when a sample of sample_bytes will not fit the receive buffer (rule: the sample is
/// larger than capacity_bytes()), naming the remedies: frame_encoding: jpeg, shared memory,
/// a lower publish_width_px, a larger net.core.rmem_max. `what` names the frames ("raw
/// 2304x1296 bgr8 frames"). nullopt when it fits or shared memory carries it.
std::optional<std::string> oversize_warning(uint64_t sample_bytes, const TransportLimits& limits,
                                            const std::string& what);

}  // namespace stereoball::stereo
