#pragma once
// Cyclone's iceoryx shared memory (Debian's libddsc is built with it): on when the Cyclone
// configuration enables it AND the iceoryx daemon (iox-roudi) runs. Without RouDi, Cyclone
// would wait for it forever at the first participant; this check turns shared memory off
// instead, so a node always starts and its samples go over the loopback network.

#include <functional>
#include <optional>
#include <string>

namespace stereoball::dds {

/// True when one of the configurations in a CYCLONEDDS_URI value (comma-separated file:// paths
/// or inline XML; later ones override earlier ones) enables <SharedMemory>. read_file returns
/// a file's text (nullopt if unreadable).
bool configuration_enables_shared_memory(
    const std::string& uri,
    const std::function<std::optional<std::string>(const std::string&)>& read_file);

/// True when an iceoryx RouDi daemon accepts connections on its socket (/tmp/roudi).
bool roudi_running();

/// What the process-wide check decided.
enum class SharedMemoryState { kNotConfigured, kOn, kOffNoRouDi };

/// Runs the check once per process (the DomainParticipant constructor calls it before the first
/// participant): configured but no RouDi -> appends an override to CYCLONEDDS_URI that turns
/// shared memory off, and logs one warning line saying so.
SharedMemoryState ensure_shared_memory_usable();

}  // namespace stereoball::dds
