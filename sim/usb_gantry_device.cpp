#include "sim/usb_gantry_device.h"

#include <linux/ioctl.h>
#include <linux/usbdevice_fs.h>
#include <umockdev.h>

#include <cerrno>
#include <cstddef>
#include <cstdio>
#include <cstring>
#include <stdexcept>

namespace acq::sim {
namespace {

constexpr std::uint8_t kEndpointOut = 0x01, kEndpointIn = 0x81;
constexpr std::uint16_t kPacketSize = 512;  // high-speed bulk

std::string HexBytes(const std::vector<std::uint8_t>& bytes) {
  std::string s;
  char b[3];
  for (std::uint8_t v : bytes) std::snprintf(b, sizeof b, "%02x", v), s += b;
  return s;
}

// Device, configuration, interface (vendor class) and the two bulk endpoints, as the kernel
// exposes them in sysfs's binary "descriptors" attribute, which libusb reads.
std::vector<std::uint8_t> Descriptors(std::uint16_t vid, std::uint16_t pid) {
  auto lo = [](std::uint16_t v) { return std::uint8_t(v & 0xFF); };
  auto hi = [](std::uint16_t v) { return std::uint8_t(v >> 8); };
  return {18,
          1,
          0x00,
          0x02,
          0,
          0,
          0,
          64,
          lo(vid),
          hi(vid),
          lo(pid),
          hi(pid),
          0x00,
          0x01,
          1,
          2,
          3,
          1,  // device
          9,
          2,
          32,
          0,
          1,
          1,
          0,
          0x80,
          50,  // configuration
          9,
          4,
          0,
          0,
          2,
          0xFF,
          0,
          0,
          0,  // interface
          7,
          5,
          kEndpointOut,
          2,
          lo(kPacketSize),
          hi(kPacketSize),
          0,  // bulk OUT
          7,
          5,
          kEndpointIn,
          2,
          lo(kPacketSize),
          hi(kPacketSize),
          0};  // bulk IN
}

// A USB string descriptor (UTF-16LE of ASCII text).
std::vector<std::uint8_t> StringDescriptor(const std::string& text) {
  std::vector<std::uint8_t> d{std::uint8_t(2 + 2 * text.size()), 3};
  for (char c : text) d.push_back(std::uint8_t(c)), d.push_back(0);
  return d;
}

gboolean OnIoctl(UMockdevIoctlBase*, UMockdevIoctlClient* client, gpointer self) {
  return static_cast<EmulatedUsbGantry*>(self)->HandleIoctl(client);
}

}  // namespace

// A submitted URB: umockdev's local copies of the usbdevfs_urb and of its buffer, written back
// to the client when the URB is reaped.
struct EmulatedUsbGantry::Urb {
  UMockdevIoctlData* urb = nullptr;
  UMockdevIoctlData* buffer = nullptr;
  ~Urb() {
    if (buffer) umockdev_ioctl_data_unref(buffer);
    if (urb) umockdev_ioctl_data_unref(urb);
  }
  usbdevfs_urb& header() const { return *reinterpret_cast<usbdevfs_urb*>(urb->data); }
  std::uint8_t* data() const { return buffer ? buffer->data : nullptr; }
  void Finish(int actual_length, int status) const {
    header().actual_length = actual_length;
    header().status = status;
  }
};

bool EmulatedUsbGantry::UnderUmockdev() {
  // umockdev answers this only once a testbed exists (it looks at the testbed's environment as
  // well as at the preload library), so ask with a throwaway one.
  UMockdevTestbed* probe = umockdev_testbed_new();
  const bool preloaded = umockdev_in_mock_environment();
  g_object_unref(probe);
  return preloaded;
}

namespace {
FirmwareOptions LeasesOnTheWallClock(FirmwareOptions firmware, double time_scale) {
  firmware.lease_time_scale = time_scale;
  return firmware;
}
}  // namespace

EmulatedUsbGantry::EmulatedUsbGantry(FirmwareOptions firmware, EmulatedUsbOptions usb)
    : firmware_options_(LeasesOnTheWallClock(firmware, usb.time_scale)),
      usb_(std::move(usb)),
      firmware_(firmware_options_) {
  testbed_ = umockdev_testbed_new();
  if (!umockdev_in_mock_environment()) {
    g_object_unref(static_cast<UMockdevTestbed*>(testbed_));
    throw std::runtime_error(
        "the simulated USB gantry needs umockdev's preload library: run under "
        "`umockdev-wrapper` or with LD_PRELOAD=libumockdev-preload.so.0");
  }
  handler_ = umockdev_ioctl_base_new();
  g_signal_connect_after(handler_, "handle-ioctl", G_CALLBACK(OnIoctl), this);
  last_sync_ = std::chrono::steady_clock::now();
  plugged_ = true;
  AddDevice();
}

EmulatedUsbGantry::~EmulatedUsbGantry() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    in_flight_.clear();
    completed_.clear();
  }
  g_object_unref(static_cast<UMockdevTestbed*>(testbed_));
  g_object_unref(static_cast<UMockdevIoctlBase*>(handler_));
}

std::string EmulatedUsbGantry::devnode() const {
  char s[32];
  std::snprintf(s, sizeof s, "/dev/bus/usb/001/%03d", devnum_);
  return s;
}

int EmulatedUsbGantry::ioctls() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return ioctls_;
}

void EmulatedUsbGantry::AddDevice() {
  auto* testbed = static_cast<UMockdevTestbed*>(testbed_);
  const std::string node = devnode();
  // The handler first, so that the device can be opened as soon as it appears.
  umockdev_testbed_attach_ioctl(testbed, node.c_str(), static_cast<UMockdevIoctlBase*>(handler_),
                                nullptr);
  char num[8];
  std::snprintf(num, sizeof num, "%03d", devnum_);
  const std::string record =
      std::string("P: /devices/usb1\nN: bus/usb/001/") + num +
      "\nE: SUBSYSTEM=usb\nE: DRIVER=usb\nE: BUSNUM=001\nE: DEVNUM=" + num +
      "\nE: DEVNAME=" + node +
      "\nE: DEVTYPE=usb_device\nA: busnum=1\\n\nA: devnum=" + std::to_string(devnum_) +
      "\\n\nA: speed=480\\n\nA: bConfigurationValue=1\\n\n" +
      "H: descriptors=" + HexBytes(Descriptors(usb_.vendor_id, usb_.product_id)) + "\n";
  GError* error = nullptr;
  if (!umockdev_testbed_add_from_string(testbed, record.c_str(), &error)) {
    const std::string why = error ? error->message : "unknown error";
    g_clear_error(&error);
    throw std::runtime_error("umockdev could not add the simulated gantry: " + why);
  }
}

void EmulatedUsbGantry::Sync() {
  const auto now = std::chrono::steady_clock::now();
  firmware_.Advance(std::chrono::duration<double>(now - last_sync_).count() * usb_.time_scale);
  last_sync_ = now;
}

void EmulatedUsbGantry::SetReplyDelay(double seconds) {
  std::lock_guard<std::mutex> lock(mutex_);
  usb_.reply_delay_s = seconds;
}

void EmulatedUsbGantry::FailFlying(int status) {
  while (!in_flight_.empty()) {
    in_flight_.front()->Finish(0, status);
    completed_.push_back(std::move(in_flight_.front()));
    in_flight_.pop_front();
  }
}

void EmulatedUsbGantry::Unplug() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!plugged_) return;
    plugged_ = false;
    FailFlying(-ENODEV);
    replies_.clear();
  }
  umockdev_testbed_remove_device(static_cast<UMockdevTestbed*>(testbed_), "/sys/devices/usb1");
}

void EmulatedUsbGantry::Plug() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (plugged_) return;
    plugged_ = true;
    ++devnum_;
    completed_.clear();  // URBs of the old device node die with it
  }
  AddDevice();
}

void EmulatedUsbGantry::ResetFirmware() {
  Unplug();
  {
    std::lock_guard<std::mutex> lock(mutex_);
    firmware_.Reset();
  }
  Plug();
}

void EmulatedUsbGantry::CompleteInTransfers() {
  const auto now = std::chrono::steady_clock::now();
  // One reply per IN transfer, as the firmware sends each frame as its own short transfer.
  while (!in_flight_.empty() && !replies_.empty() && replies_.front().ready <= now) {
    std::unique_ptr<Urb> urb = std::move(in_flight_.front());
    in_flight_.pop_front();
    std::vector<std::uint8_t>& bytes = replies_.front().bytes;
    const std::size_t n = std::min<std::size_t>(bytes.size(), urb->header().buffer_length);
    std::memcpy(urb->data(), bytes.data(), n);
    bytes.erase(bytes.begin(), bytes.begin() + std::ptrdiff_t(n));
    if (bytes.empty()) replies_.pop_front();
    urb->Finish(int(n), 0);
    completed_.push_back(std::move(urb));
  }
}

bool EmulatedUsbGantry::HandleIoctl(void* client_pointer) {
  auto* client = static_cast<UMockdevIoctlClient*>(client_pointer);
  const unsigned long request = umockdev_ioctl_client_get_request(client);
  UMockdevIoctlData* arg = umockdev_ioctl_client_get_arg(client);
  std::lock_guard<std::mutex> lock(mutex_);
  ++ioctls_;
  Sync();
  const bool current = plugged_ && devnode() == umockdev_ioctl_client_get_devnode(client);
  const bool reap = request == USBDEVFS_REAPURB || request == USBDEVFS_REAPURBNDELAY;
  // What a vanished device answers: transfers already ended can still be reaped (the kernel's
  // USBDEVFS_CAP_REAP_AFTER_DISCONNECT), everything else fails with ENODEV.
  if (!current && !(reap && !completed_.empty())) {
    umockdev_ioctl_client_complete(client, -1, ENODEV);
    return true;
  }
  switch (request) {
    case USBDEVFS_GET_CAPABILITIES: {
      UMockdevIoctlData* d = umockdev_ioctl_data_resolve(arg, 0, sizeof(std::uint32_t), nullptr);
      *reinterpret_cast<std::uint32_t*>(d->data) =
          USBDEVFS_CAP_BULK_CONTINUATION | USBDEVFS_CAP_NO_PACKET_SIZE_LIM |
          USBDEVFS_CAP_REAP_AFTER_DISCONNECT | USBDEVFS_CAP_ZERO_PACKET;
      umockdev_ioctl_data_unref(d);
      umockdev_ioctl_client_complete(client, 0, 0);
      return true;
    }
    case USBDEVFS_CLAIMINTERFACE:
    case USBDEVFS_RELEASEINTERFACE:
    case USBDEVFS_DISCONNECT_CLAIM:
    case USBDEVFS_SETINTERFACE:
    case USBDEVFS_CLEAR_HALT:
    case USBDEVFS_RESET:
    case USBDEVFS_RESETEP:
      umockdev_ioctl_client_complete(client, 0, 0);
      return true;
    case USBDEVFS_GETDRIVER:  // no kernel driver bound to our vendor interface
    case USBDEVFS_IOCTL:      // (libusb asks through this one to detach it)
      umockdev_ioctl_client_complete(client, -1, ENODATA);
      return true;
    case USBDEVFS_SUBMITURB: {
      auto urb = std::make_unique<Urb>();
      urb->urb = umockdev_ioctl_data_resolve(arg, 0, sizeof(usbdevfs_urb), nullptr);
      const usbdevfs_urb& h = urb->header();
      if (h.buffer_length > 0)
        urb->buffer = umockdev_ioctl_data_resolve(urb->urb, offsetof(usbdevfs_urb, buffer),
                                                  std::size_t(h.buffer_length), nullptr);
      if (h.type == USBDEVFS_URB_TYPE_CONTROL && h.buffer_length >= 8) {
        // The setup packet, then the data stage: only GET_DESCRIPTOR(STRING) is asked for.
        const std::uint8_t* setup = urb->data();
        std::vector<std::uint8_t> reply;
        if (setup[0] == 0x80 && setup[1] == 6 && setup[3] == 3) {
          const int index = setup[2];
          reply = index == 0   ? std::vector<std::uint8_t>{4, 3, 0x09, 0x04}  // en-US
                  : index == 1 ? StringDescriptor("acq")
                  : index == 2 ? StringDescriptor("acq gantry controller (simulated)")
                  : index == 3 ? StringDescriptor(usb_.serial)
                               : std::vector<std::uint8_t>{};
        }
        const std::size_t n = std::min<std::size_t>(reply.size(), h.buffer_length - 8);
        std::memcpy(urb->data() + 8, reply.data(), n);
        urb->Finish(int(n), reply.empty() ? -EPIPE : 0);  // a stall for anything else
        completed_.push_back(std::move(urb));
      } else if (h.type == USBDEVFS_URB_TYPE_BULK && h.endpoint == kEndpointOut) {
        std::vector<std::uint8_t> reply;
        firmware_.Receive(urb->data(), std::size_t(h.buffer_length), &reply);
        if (!reply.empty())
          replies_.push_back({std::move(reply),
                              std::chrono::steady_clock::now() +
                                  std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                      std::chrono::duration<double>(usb_.reply_delay_s))});
        urb->Finish(h.buffer_length, 0);
        completed_.push_back(std::move(urb));
      } else if (h.type == USBDEVFS_URB_TYPE_BULK && h.endpoint == kEndpointIn) {
        in_flight_.push_back(std::move(urb));
      } else {
        umockdev_ioctl_client_complete(client, -1, EINVAL);
        return true;
      }
      umockdev_ioctl_client_complete(client, 0, 0);
      CompleteInTransfers();
      return true;
    }
    case USBDEVFS_REAPURB:
    case USBDEVFS_REAPURBNDELAY: {
      CompleteInTransfers();
      if (completed_.empty()) {
        umockdev_ioctl_client_complete(client, -1, EAGAIN);
        return true;
      }
      std::unique_ptr<Urb> urb = std::move(completed_.front());
      completed_.pop_front();
      UMockdevIoctlData* pointer = umockdev_ioctl_data_resolve(arg, 0, sizeof(void*), nullptr);
      umockdev_ioctl_data_set_ptr(pointer, 0, urb->urb);
      umockdev_ioctl_data_unref(pointer);
      umockdev_ioctl_client_complete(client, 0, 0);
      return true;
    }
    case USBDEVFS_DISCARDURB: {
      const auto address = reinterpret_cast<gulong>(*reinterpret_cast<void**>(arg->data));
      for (auto it = in_flight_.begin(); it != in_flight_.end(); ++it) {
        if ((*it)->urb->client_addr != address) continue;
        (*it)->Finish(0, -ENOENT);
        completed_.push_back(std::move(*it));
        in_flight_.erase(it);
        umockdev_ioctl_client_complete(client, 0, 0);
        return true;
      }
      umockdev_ioctl_client_complete(client, -1, EINVAL);
      return true;
    }
    default:
      std::fprintf(stderr, "simulated gantry: unhandled usbfs ioctl 0x%lx\n", request);
      return false;
  }
}

}  // namespace acq::sim
