#include "dlo/mrpt/velodyne_capture_check.h"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <vector>

#include "dlo/files/error.h"

namespace dlo {

namespace {

constexpr uint32_t kLinkTypeEthernet = 1;
/// libpcap's largest packet for Ethernet (MAXIMUM_SNAPLEN); a snap length of 0 means this.
constexpr uint32_t kMaxSnapLength = 262144;
constexpr uint16_t kDataPort = 2368;
constexpr uint16_t kPositionPort = 8308;
/// What CVelodyneScanner copies out of a packet: 42 bytes of Ethernet + IPv4 + UDP headers, then
/// the payload.
constexpr size_t kDataPacketBytes = 42 + 1206;
constexpr size_t kPositionPacketBytes = 42 + 512;
/// Enough of a packet to evaluate the driver's filter (the IPv4 header is at most 60 bytes).
constexpr size_t kPrefixBytes = 14 + 60 + 4;

uint16_t be16(const uint8_t* p) {
  return static_cast<uint16_t>(p[0] << 8 | p[1]);
}

/// Whether MRPT's BPF filter "(udp dst port 2368 || udp dst port 8308)" accepts the packet whose
/// first `n` bytes are `p` (n is at most its captured length). A load past the captured length
/// rejects the packet, as in BPF.
bool passesDriverFilter(const uint8_t* p, size_t n) {
  auto isVelodynePort = [](uint16_t port) { return port == kDataPort || port == kPositionPort; };
  if (n < 14) return false;
  const uint16_t ether_type = be16(p + 12);
  if (ether_type == 0x86dd) return n >= 58 && p[20] == 17 && isVelodynePort(be16(p + 56));
  if (ether_type != 0x0800 || n < 24 || p[23] != 17) return false;
  if ((be16(p + 20) & 0x1fff) != 0) return false;  // a later fragment has no UDP header
  const size_t port_at = 14 + 4 * static_cast<size_t>(p[14] & 0x0f) + 2;
  return n >= port_at + 2 && isVelodynePort(be16(p + port_at));
}

/// Reads the capture one record at a time, in either format, and checks each packet.
class CaptureWalker {
 public:
  explicit CaptureWalker(const std::string& path) : path_(path), in_(path, std::ios::binary) {
    if (!in_) fail("no such file or not readable");
    in_.seekg(0, std::ios::end);
    size_ = static_cast<uint64_t>(in_.tellg());
    in_.seekg(0);
  }

  VelodyneCaptureSummary walk() {
    uint8_t magic[4];
    if (!readAt(0, magic, 4)) fail("it is too short for a pcap header");
    const uint32_t le = uint32_t(magic[0]) | uint32_t(magic[1]) << 8 | uint32_t(magic[2]) << 16 |
                        uint32_t(magic[3]) << 24;
    if (le == 0x0A0D0D0A) {
      walkPcapng();
    } else if (le == 0xa1b2c3d4 || le == 0xa1b23c4d || le == 0xd4c3b2a1 || le == 0x4d3cb2a1) {
      big_endian_ = le == 0xd4c3b2a1 || le == 0x4d3cb2a1;
      walkPcap();
    } else {
      fail("it is not a pcap or pcapng capture (unknown magic number)");
    }
    if (summary_.velodyne_packets == 0) {
      fail("it holds no Velodyne packet (UDP to port 2368 or 8308 over Ethernet) in its " +
           std::to_string(summary_.packets) + " packets");
    }
    return summary_;
  }

 private:
  [[noreturn]] void fail(const std::string& why) const {
    throw InputError("cannot read Velodyne capture '" + path_ + "': " + why + ".");
  }
  /// The capture is malformed at `offset` (a record or block).
  [[noreturn]] void corrupt(uint64_t offset, const std::string& why) const {
    fail("it is corrupt after " + std::to_string(summary_.packets) +
         " packets: the record at byte offset " + std::to_string(offset) + " " + why);
  }
  /// The packet whose data starts at `offset` cannot be given to the driver.
  [[noreturn]] void badPacket(uint64_t offset, const std::string& why) const {
    fail("packet " + std::to_string(summary_.packets) + " (byte offset " + std::to_string(offset) +
         ") " + why);
  }

  bool readAt(uint64_t offset, void* out, size_t n) {
    if (offset > size_ || size_ - offset < n) return false;
    in_.clear();
    in_.seekg(static_cast<std::streamoff>(offset));
    return static_cast<bool>(in_.read(static_cast<char*>(out), static_cast<std::streamsize>(n)));
  }
  uint16_t u16(const uint8_t* p) const {
    return big_endian_ ? be16(p) : static_cast<uint16_t>(p[0] | p[1] << 8);
  }
  uint32_t u32(const uint8_t* p) const {
    return big_endian_ ? uint32_t(be16(p)) << 16 | be16(p + 2)
                       : uint32_t(u16(p + 2)) << 16 | u16(p);
  }
  static uint32_t snapLength(uint32_t declared) {
    return declared == 0 || declared > kMaxSnapLength ? kMaxSnapLength : declared;
  }
  void requireEthernet(uint32_t link_type) const {
    if (link_type != kLinkTypeEthernet) {
      fail("its link type is " + std::to_string(link_type) +
           ", not Ethernet (1), and MRPT's Velodyne driver reads Ethernet frames only");
    }
  }

  /// The packet at `offset`, of which libpcap returns `captured` bytes. The filter is evaluated
  /// exactly as the driver's (a packet counted here must be one it accepts, or it would loop
  /// forever on a capture it finds empty; one it accepts must be checked here).
  void checkPacket(uint64_t offset, uint64_t captured) {
    uint8_t p[kPrefixBytes];
    const size_t n = static_cast<size_t>(std::min<uint64_t>(captured, kPrefixBytes));
    if (!readAt(offset, p, n)) corrupt(offset, "ends past the end of the file");
    if (passesDriverFilter(p, n)) {
      ++summary_.velodyne_packets;
      // The driver tells data from position packets by the port at a fixed offset, then copies
      // a whole payload out of the packet.
      if (n < 38) {
        badPacket(offset, "is too short for the UDP header the driver reads");
      }
      const uint16_t port = be16(p + 36);
      const size_t needed = port == kDataPort       ? kDataPacketBytes
                            : port == kPositionPort ? kPositionPacketBytes
                                                    : 0;
      if (captured < needed) {
        badPacket(offset, "is a Velodyne " + std::string(port == kDataPort ? "data" : "position") +
                              " packet captured with " + std::to_string(captured) + " of its " +
                              std::to_string(needed) + " bytes (was the snap length too short?)");
      }
    }
    ++summary_.packets;
  }

  void walkPcap() {
    uint8_t header[24];
    if (!readAt(0, header, 24)) fail("it is too short for a pcap header");
    if (u16(header + 4) != 2 || u16(header + 6) != 4) {
      fail("its pcap version is " + std::to_string(u16(header + 4)) + "." +
           std::to_string(u16(header + 6)) + ", not 2.4");
    }
    const uint32_t snap = snapLength(u32(header + 16));
    requireEthernet(u32(header + 20));
    for (uint64_t at = 24; at < size_;) {
      uint8_t record[16];
      if (!readAt(at, record, 16)) return;  // a record header cut by the end: libpcap stops
      const uint32_t caplen = u32(record + 8);
      if (caplen > kMaxSnapLength) {
        corrupt(at, "has a capture length of " + std::to_string(caplen) + " bytes (at most " +
                        std::to_string(kMaxSnapLength) + ")");
      }
      if (size_ - at - 16 < caplen) return;  // the last packet cut by the end: libpcap stops
      checkPacket(at + 16, std::min(caplen, snap));
      at += 16 + uint64_t(caplen);
    }
  }

  /// Reads the options of an interface description block (body offsets [from, to)) the way
  /// libpcap does, which fails on malformed ones.
  void checkInterfaceOptions(uint64_t block, uint64_t from, uint64_t to) {
    bool saw_resolution = false, saw_offset = false;
    while (from < to) {
      uint8_t option[5] = {};
      if (to - from < 4 || !readAt(from, option, 4)) corrupt(block, "has a truncated option");
      const uint16_t code = u16(option), length = u16(option + 2);
      const uint64_t padded = (uint64_t(length) + 3) / 4 * 4;
      if (to - from - 4 < padded) corrupt(block, "has an option longer than its block");
      if (code == 0) {  // end of options
        if (length != 0) corrupt(block, "has an end-of-options mark with a value");
        return;
      }
      if (code == 9) {  // if_tsresol: 10^-n or 2^-n seconds
        if (length != 1 || saw_resolution || !readAt(from + 4, option + 4, 1)) {
          corrupt(block, "has a bad time stamp resolution option");
        }
        const int exponent = option[4] & 0x7f;
        if (exponent > ((option[4] & 0x80) ? 62 : 18)) {
          corrupt(block, "has a time stamp resolution finer than libpcap reads");
        }
        saw_resolution = true;
      } else if (code == 14) {  // if_tsoffset
        if (length != 8 || saw_offset) corrupt(block, "has a bad time stamp offset option");
        saw_offset = true;
      }
      from += 4 + padded;
    }
  }

  /// pcapng, as libpcap 1.10 reads it; where libpcap would fail part way (and MRPT's driver
  /// would stop there, or loop forever when no packet came before) the capture is rejected, except
  /// for a last block cut by the end of the file (an interrupted capture), where both stop.
  void walkPcapng() {
    std::vector<uint32_t> snap_of_interface;
    for (uint64_t at = 0; at < size_;) {
      uint8_t head[12];
      if (!readAt(at, head, 12)) return;  // a block cut by the end: libpcap stops
      const bool section = be16(head) == 0x0A0D && be16(head + 2) == 0x0D0A;
      if (section != (at == 0)) {
        fail(at == 0 ? "it does not start with a pcapng section header"
                     : "it has more than one section (captures joined into one file)");
      }
      if (section) {
        // The byte-order magic sets the byte order of the section.
        const uint32_t bom = uint32_t(head[8]) | uint32_t(head[9]) << 8 | uint32_t(head[10]) << 16 |
                             uint32_t(head[11]) << 24;
        if (bom != 0x1A2B3C4D && bom != 0x4D3C2B1A) corrupt(at, "has a bad section header");
        big_endian_ = bom == 0x4D3C2B1A;
      }
      const uint32_t type = u32(head);
      const uint32_t length = u32(head + 4);
      // libpcap's own limit is a little above: the largest packet plus 128 KiB of options.
      if (length < 12 || length % 4 != 0 || length > kMaxSnapLength + 131072) {
        corrupt(at, "has a block length of " + std::to_string(length) + " bytes");
      }
      if (size_ - at < length) return;  // the last block cut by the end: libpcap stops
      uint8_t trailer[4];
      if (!readAt(at + length - 4, trailer, 4) || u32(trailer) != length) {
        corrupt(at, "has a block whose trailing length differs from its leading one");
      }
      const uint64_t body = at + 8;
      const uint32_t body_length = length - 12;
      uint8_t fields[20] = {};
      auto need = [&](uint32_t n) {
        if (body_length < n || !readAt(body, fields, n)) corrupt(at, "has a block too short");
      };
      if (section) {
        if (length < 28) corrupt(at, "has a section header too short");
        need(8);
        if (u16(fields + 4) != 1 || u16(fields + 6) != 0) {
          fail("its pcapng version is " + std::to_string(u16(fields + 4)) + "." +
               std::to_string(u16(fields + 6)) + ", not 1.0");
        }
      } else if (type == 1) {  // interface description: link type, snap length, options
        need(8);
        requireEthernet(u16(fields));
        snap_of_interface.push_back(snapLength(u32(fields + 4)));
        checkInterfaceOptions(at, body + 8, body + body_length);
      } else if (type == 6 || type == 2 || type == 3) {  // enhanced, obsolete, simple packet
        if (snap_of_interface.empty()) corrupt(at, "is a packet before any interface description");
        // libpcap cuts every packet to the snap length of the first interface.
        const uint32_t snap = snap_of_interface.front();
        if (type == 3) {  // its length is the original length
          need(4);
          const uint32_t returned = std::min(u32(fields), snap);
          if (returned > body_length - 4) corrupt(at, "has a packet longer than its block");
          checkPacket(body + 4, returned);
        } else {
          need(20);
          const uint32_t interface = type == 6 ? u32(fields) : u16(fields);
          if (interface >= snap_of_interface.size()) {
            corrupt(at, "is a packet of interface " + std::to_string(interface) +
                            ", which the section does not describe");
          }
          const uint32_t caplen = u32(fields + 12);
          if (caplen > body_length - 20) corrupt(at, "has a packet longer than its block");
          checkPacket(body + 20, std::min(caplen, snap));
        }
      }
      at += length;
    }
  }

  std::string path_;
  std::ifstream in_;
  uint64_t size_ = 0;
  bool big_endian_ = false;
  VelodyneCaptureSummary summary_;
};

}  // namespace

VelodyneCaptureSummary checkVelodyneCapture(const std::string& path) {
  return CaptureWalker(path).walk();
}

}  // namespace dlo
