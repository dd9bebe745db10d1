#pragma once
// Internal to the HDF5 reader/writer: an owning hid_t and error-stack silencing.
#include <dvs_driver/formats/event_format.h>

#include <hdf5.h>

#include <string>
#include <utility>

namespace dvs_driver
{
namespace formats
{
namespace hdf5
{
/// Owns an HDF5 identifier; closes it with H5Idec_ref (works for files, groups, datasets,
/// dataspaces, types, property lists, attributes).
class Handle
{
public:
  Handle() = default;
  explicit Handle(hid_t id) : id_(id) {}
  ~Handle() { reset(); }
  Handle(Handle&& o) noexcept : id_(std::exchange(o.id_, H5I_INVALID_HID)) {}
  Handle& operator=(Handle&& o) noexcept
  {
    if (this != &o)
    {
      reset();
      id_ = std::exchange(o.id_, H5I_INVALID_HID);
    }
    return *this;
  }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  void reset()
  {
    if (id_ >= 0)
      H5Idec_ref(id_);
    id_ = H5I_INVALID_HID;
  }
  hid_t get() const { return id_; }
  bool valid() const { return id_ >= 0; }
  explicit operator bool() const { return valid(); }

private:
  hid_t id_ = H5I_INVALID_HID;
};

/// Silences libhdf5's automatic error printing for this scope (errors become our exceptions).
class Quiet
{
public:
  Quiet()
  {
    H5Eget_auto2(H5E_DEFAULT, &func_, &data_);
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  }
  ~Quiet() { H5Eset_auto2(H5E_DEFAULT, func_, data_); }
  Quiet(const Quiet&) = delete;
  Quiet& operator=(const Quiet&) = delete;

private:
  H5E_auto2_t func_ = nullptr;
  void* data_ = nullptr;
};

/// The innermost message of the current HDF5 error stack ("" when empty).
std::string lastError();

constexpr H5Z_filter_t kBloscFilter = 32001;
}  // namespace hdf5
}  // namespace formats
}  // namespace dvs_driver
