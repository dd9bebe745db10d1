#include <dvs_driver/aedat_reader.h>
#include <dvs_driver/dvs128_decoder.h>

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <algorithm>
#include <vector>

namespace dvs_driver
{
namespace
{
inline uint32_t be32(const uint8_t* p)
{
  return (uint32_t(p[0]) << 24) | (uint32_t(p[1]) << 16) | (uint32_t(p[2]) << 8) | uint32_t(p[3]);
}

// A header line: '#', then text (tab or >= 0x20, UTF-8 bytes allowed), ending in "\n".
// Returns the offset just past the line, or 0 when [pos, size) does not start with one.
size_t headerLineEnd(const uint8_t* data, size_t size, size_t pos)
{
  if (pos >= size || data[pos] != '#')
    return 0;
  for (size_t i = pos + 1; i < size; ++i)
  {
    const uint8_t c = data[i];
    if (c == '\n')
      return i + 1;
    if (c < 0x20 && c != '\t' && c != '\r')
      return 0;
  }
  return 0;
}

std::string lineText(const uint8_t* data, size_t begin, size_t end)
{
  while (end > begin && (data[end - 1] == '\n' || data[end - 1] == '\r'))
    --end;
  return std::string(reinterpret_cast<const char*>(data + begin), end - begin);
}
}  // namespace

size_t findAedatDataOffset(const uint8_t* data, size_t size)
{
  size_t pos = 0;
  while (true)
  {
    const size_t end = headerLineEnd(data, size, pos);
    if (end == 0)
      return pos;
    const std::string line = lineText(data, pos, end);
    pos = end;
    if (line.rfind("#End Of ASCII Header", 0) == 0)
      return pos;
  }
}

namespace
{
// The value of a jAER preference line `<entry key="KEY" value="VALUE"/>` ("" when not this key).
std::string preferenceValue(const std::string& line, const char* key)
{
  const std::string k = std::string("key=\"") + key + "\" value=\"";
  const size_t a = line.find(k);
  if (a == std::string::npos)
    return "";
  const size_t b = a + k.size(), e = line.find('"', b);
  return e == std::string::npos ? "" : line.substr(b, e - b);
}

// DAVIS IMU full scales from the header's jAER preferences: the named settings first, else the
// MPU-6150 configuration registers (bits 3-4 select 2/4/8/16 g and 250/500/1000/2000 deg/s).
void parseImuScale(const std::string& line, AedatInfo& info)
{
  static const char* const kAccel[] = {"ImuAccelScaleG2", "ImuAccelScaleG4", "ImuAccelScaleG8", "ImuAccelScaleG16"};
  static const char* const kGyro[] = {"GyroFullScaleDegPerSec250", "GyroFullScaleDegPerSec500",
                                      "GyroFullScaleDegPerSec1000", "GyroFullScaleDegPerSec2000"};
  std::string v = preferenceValue(line, "ImuAccelScale");
  for (int k = 0; k < 4 && !v.empty(); ++k)
    if (v == kAccel[k])
    {
      info.imu_accel_full_scale_g = 2 << k;
      info.imu_accel_scale_named = info.imu_scale_from_header = true;
    }
  v = preferenceValue(line, "ImuGyroScale");
  for (int k = 0; k < 4 && !v.empty(); ++k)
    if (v == kGyro[k])
    {
      info.imu_gyro_full_scale_deg_s = 250 << k;
      info.imu_gyro_scale_named = info.imu_scale_from_header = true;
    }
  v = preferenceValue(line, "CPLDByte.imu4_ACCEL_CONFIG");
  if (!v.empty() && !info.imu_accel_scale_named)
  {
    info.imu_accel_full_scale_g = 2 << ((std::atoi(v.c_str()) >> 3) & 3);
    info.imu_scale_from_header = true;
  }
  v = preferenceValue(line, "CPLDByte.imu3_GYRO_CONFIG");
  if (!v.empty() && !info.imu_gyro_scale_named)
  {
    info.imu_gyro_full_scale_deg_s = 250 << ((std::atoi(v.c_str()) >> 3) & 3);
    info.imu_scale_from_header = true;
  }
}

// Checks magic and version, finds the data offset, and reads the sensor from the header
// (`# AEChip:`, else the HardwareInterface line). Returns false when the header does not say.
bool parseAedatHeader(const uint8_t* data, size_t size, const std::string& name, AedatInfo& info)
{
  static const char kMagic[] = "#!AER-DAT";
  if (size < sizeof(kMagic) - 1 || std::memcmp(data, kMagic, sizeof(kMagic) - 1) != 0)
    throw AedatError(name + ": not an AEDAT file (it does not start with `#!AER-DAT`)");
  const size_t first_end = headerLineEnd(data, size, 0);
  const std::string first = first_end ? lineText(data, 0, first_end) : std::string();
  if (first != "#!AER-DAT2.0")
    throw AedatError(name + ": unsupported AEDAT version `" + first.substr(0, 40) + "` (only #!AER-DAT2.0 is read)");
  info.data_offset = findAedatDataOffset(data, size);
  std::string hw;
  for (size_t pos = 0; pos < info.data_offset;)
  {
    const size_t end = headerLineEnd(data, size, pos);
    const std::string line = lineText(data, pos, end);
    pos = end;
    parseImuScale(line, info);
    if (line.rfind("# AEChip:", 0) == 0)
      info.ae_chip = line.substr(line.find_first_not_of(' ', 9) == std::string::npos ? line.size()
                                                                                          : line.find_first_not_of(' ', 9));
    else if (line.rfind("# HardwareInterface:", 0) == 0)
      hw = line;
  }
  const std::string chip = info.ae_chip.empty() ? hw : info.ae_chip;
  if (chip.find("DAVIS346") != std::string::npos)
    info.sensor = AedatSensor::DAVIS346;
  else if (chip.find("DAVIS240") != std::string::npos)
    info.sensor = AedatSensor::DAVIS240;
  else if (chip.find("DVS128") != std::string::npos)
    info.sensor = AedatSensor::DVS128;
  else
    return false;
  return true;
}

// Sensor not named in the header: DVS128 if every address fits its 16 bits, else an error.
void checkDvs128Addresses(const uint8_t* records, uint64_t n, const std::string& name, const AedatInfo& info)
{
  for (uint64_t i = 0; i < n; ++i)
    if (be32(records + 8 * i) > 0xFFFFu)
      throw AedatError(name + ": cannot tell the sensor: no `# AEChip:` header line names DVS128, DAVIS240 "
                              "or DAVIS346, and addresses exceed the DVS128's 16 bits (AEChip: `" +
                       info.ae_chip + "`)");
}

void setSensorSize(AedatInfo& info, uint32_t& width, uint32_t& height)
{
  switch (info.sensor)
  {
    case AedatSensor::DVS128:
      info.sensor_name = "DVS128";
      width = 128;
      height = 128;
      break;
    case AedatSensor::DAVIS240:
      info.sensor_name = "DAVIS240";
      width = 240;
      height = 180;
      break;
    case AedatSensor::DAVIS346:
      info.sensor_name = "DAVIS346";
      width = 346;
      height = 260;
      break;
  }
}
}  // namespace

// The records of one file in order, in as many pieces as wanted: int32 wraps unwrapped and
// backwards times clamped across pieces.
struct AedatRecordDecoder
{
  int64_t wrap_offset = 0;
  int32_t last_raw = 0;
  int64_t last_t_us = INT64_MIN;
  bool first = true;
  EventValidator raw;  // the file's times before clamping, clamps, records outside the sensor
  // The DAVIS IMU sample being assembled: codes 0..next_code-1 seen, all at imu_t_us.
  int next_code = 0;
  int16_t imu_raw[7] = {0, 0, 0, 0, 0, 0, 0};
  int64_t imu_t_us = 0;
  int64_t last_imu_t_us = INT64_MIN;
  size_t imu_keep = SIZE_MAX;  // samples kept in the IMU output between takes

  // One IMU record (code, raw value) at t_us; a complete 7th record appends the sample.
  void imuRecord(uint32_t addr, int64_t t_us, AedatInfo& info, ImuVector* imu)
  {
    const int code = static_cast<int>((addr >> 28) & 7u);
    const int16_t value = static_cast<int16_t>((addr >> 12) & 0xFFFFu);
    if (code != next_code || (code > 0 && t_us != imu_t_us))
    {
      info.imu_dropped += static_cast<uint64_t>(next_code);  // the incomplete sample so far
      next_code = 0;
      if (code != 0)
      {
        ++info.imu_dropped;
        return;
      }
    }
    imu_raw[code] = value;
    imu_t_us = t_us;
    if (++next_code < 7)
      return;
    next_code = 0;
    if (t_us < last_imu_t_us || !imu || imu->size() >= imu_keep)
    {
      info.imu_dropped += 7;
      return;
    }
    last_imu_t_us = t_us;
    const double accel_lsb = 32768.0 / info.imu_accel_full_scale_g;  // LSB per g
    const double gyro_lsb = gyroLsbPerDegS(info.imu_gyro_full_scale_deg_s);
    ImuSample s;
    s.t_ns = t_us * 1000;
    for (int a = 0; a < 3; ++a)
    {
      s.accel[a] = imu_raw[a] / accel_lsb * kStandardGravity;
      s.gyro[a] = imu_raw[4 + a] / gyro_lsb * (M_PI / 180.0);
    }
    s.temperature_c = imu_raw[3] / 340.0 + 35.0;
    imu->push_back(s);
    ++info.imu_decoded;
  }

  /// The records are over: an IMU sample still incomplete is dropped.
  void finish(AedatInfo& info)
  {
    info.imu_dropped += static_cast<uint64_t>(next_code);
    next_code = 0;
  }

  static double gyroLsbPerDegS(double full_scale)
  {
    // MPU-6150 datasheet: 131, 65.5, 32.8, 16.4 LSB per deg/s.
    return full_scale <= 250 ? 131.0 : full_scale <= 500 ? 65.5 : full_scale <= 1000 ? 32.8 : 16.4;
  }

  void decode(const uint8_t* records, uint64_t n, AedatInfo& info, uint32_t W, uint32_t H, EventVector& out,
              ImuVector* imu = nullptr)
  {
    const bool dvs128 = info.sensor == AedatSensor::DVS128;
    for (uint64_t i = 0; i < n; ++i)
    {
      const uint8_t* r = records + 8 * i;
      const uint32_t addr = be32(r);
      const int32_t ts = static_cast<int32_t>(be32(r + 4));
      // Unwrap int32 overflow: a jump back by more than half the range is a wrap, not disorder.
      if (!first && static_cast<int64_t>(ts) - last_raw < -(int64_t(1) << 31))
      {
        wrap_offset += int64_t(1) << 32;
        ++info.timestamp_wraps;
      }
      first = false;
      last_raw = ts;
      Event e;
      if (dvs128)
      {
        if (addr > 0xFFFFu)
        {
          ++info.out_of_range;
          raw.countOutside();
          continue;
        }
        if (!decodeDvs128Address(addr, e.x, e.y, e.polarity))
        {
          ++info.sync_events;
          continue;
        }
      }
      else
      {
        if (addr & 0x80000000u)
        {
          if ((addr & 0x80000C00u) == 0x80000C00u)
          {
            ++info.imu_samples;
            imuRecord(addr, wrap_offset + ts, info, imu);
          }
          else
            ++info.aps_samples;
          continue;
        }
        if (addr & 0x400u)
        {
          ++info.sync_events;
          continue;
        }
        const uint32_t y_up = (addr >> 22) & 0x1FFu;
        const uint32_t raw_x = (addr >> 12) & 0x3FFu;
        if (raw_x >= W || y_up >= H)
        {
          ++info.out_of_range;
          raw.countOutside();
          continue;
        }
        e.x = static_cast<uint16_t>(W - 1 - raw_x);
        e.y = static_cast<uint16_t>(H - 1 - y_up);
        e.polarity = (addr >> 11) & 1u;
      }
      int64_t t_us = wrap_offset + ts;
      raw.checkTime(t_us * 1000);
      if (t_us < last_t_us)
      {
        ++info.non_monotonic;
        raw.countClamped();
        t_us = last_t_us;
      }
      last_t_us = t_us;
      e.t_ns = t_us * 1000;
      out.push_back(e);
      ++info.dvs_events;
    }
    info.checks = raw.checks();
  }
};

AedatRecording readAedat(const uint8_t* data, size_t size, const std::string& name)
{
  AedatRecording rec;
  AedatInfo& info = rec.info;
  const bool known = parseAedatHeader(data, size, name, info);
  const uint8_t* records = data + info.data_offset;
  const size_t record_bytes = size - info.data_offset;
  info.records = record_bytes / 8;
  info.truncated_bytes = record_bytes % 8;
  if (!known)
  {
    checkDvs128Addresses(records, info.records, name, info);
    info.sensor = AedatSensor::DVS128;
  }
  EventStream& stream = rec.stream;
  setSensorSize(info, stream.width, stream.height);
  stream.events.reserve(info.records);
  AedatRecordDecoder decoder;
  decoder.raw.setSensor(stream.width, stream.height);
  decoder.decode(records, info.records, info, stream.width, stream.height, stream.events, &rec.imu);
  decoder.finish(info);
  return rec;
}

AedatRecording readAedat(const std::string& path)
{
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw AedatError(path + ": cannot open AEDAT file: " + std::strerror(errno));
  std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad())
    throw AedatError(path + ": read error");
  return readAedat(bytes.data(), bytes.size(), path);
}

AedatFileSource::AedatFileSource(const std::string& path) : in_(path, std::ios::binary), decoder_(new AedatRecordDecoder)
{
  info_.name = path;
  if (!in_)
    throw AedatError(path + ": cannot open AEDAT file: " + std::strerror(errno));
  in_.seekg(0, std::ios::end);
  const uint64_t file_size = static_cast<uint64_t>(in_.tellg());
  in_.seekg(0);
  // Read the header: a prefix that grows until its last header line is complete.
  std::vector<uint8_t> prefix;
  size_t want = 65536;
  bool known = false;
  while (true)
  {
    prefix.resize(static_cast<size_t>(std::min<uint64_t>(want, file_size)));
    in_.seekg(0);
    in_.read(reinterpret_cast<char*>(prefix.data()), static_cast<std::streamsize>(prefix.size()));
    if (!in_)
      throw AedatError(path + ": read error");
    known = parseAedatHeader(prefix.data(), prefix.size(), path, aedat_);
    const size_t off = aedat_.data_offset;
    const bool cut = prefix.size() < file_size && off < prefix.size() && prefix[off] == '#' &&
                     std::memchr(prefix.data() + off, '\n', prefix.size() - off) == nullptr;
    if (!cut)
      break;
    want *= 2;
    aedat_ = AedatInfo();
  }
  aedat_.records = (file_size - aedat_.data_offset) / 8;
  aedat_.truncated_bytes = static_cast<size_t>((file_size - aedat_.data_offset) % 8);
  if (!known)
  {
    // The header does not name the sensor: every address must fit the DVS128 (read in pieces).
    in_.seekg(static_cast<std::streamoff>(aedat_.data_offset));
    for (uint64_t done = 0; done < aedat_.records;)
    {
      const uint64_t n = std::min<uint64_t>(aedat_.records - done, 131072);
      bytes_.resize(static_cast<size_t>(n * 8));
      in_.read(reinterpret_cast<char*>(bytes_.data()), static_cast<std::streamsize>(bytes_.size()));
      if (!in_)
        throw AedatError(path + ": read error");
      checkDvs128Addresses(bytes_.data(), n, path, aedat_);
      done += n;
    }
    aedat_.sensor = AedatSensor::DVS128;
  }
  setSensorSize(aedat_, info_.width, info_.height);
  info_.sensor_name = aedat_.sensor_name;
  info_.format = "AEDAT 2.0";
  info_.truncated_bytes = aedat_.truncated_bytes;
  rewind();
}

AedatFileSource::~AedatFileSource() = default;

size_t AedatFileSource::read(EventVector& out, size_t max_events)
{
  const size_t before = out.size();
  while (out.size() - before < max_events && next_record_ < aedat_.records)
  {
    // Enough records for the events still wanted (fewer when some are not pixel events).
    const uint64_t n = std::min<uint64_t>(aedat_.records - next_record_, max_events - (out.size() - before));
    bytes_.resize(static_cast<size_t>(n * 8));
    in_.read(reinterpret_cast<char*>(bytes_.data()), static_cast<std::streamsize>(bytes_.size()));
    if (!in_)
      throw AedatError(info_.name + ": read error at record " + std::to_string(next_record_));
    decoder_->decode(bytes_.data(), n, aedat_, info_.width, info_.height, out, &imu_);
    next_record_ += n;
    if (next_record_ == aedat_.records)
      decoder_->finish(aedat_);
  }
  return out.size() - before;
}

size_t AedatFileSource::takeImu(ImuVector& out)
{
  const size_t n = imu_.size();
  out.insert(out.end(), imu_.begin(), imu_.end());
  imu_.clear();
  return n;
}

void AedatFileSource::rewind()
{
  in_.clear();
  in_.seekg(static_cast<std::streamoff>(aedat_.data_offset));
  *decoder_ = AedatRecordDecoder();
  decoder_->raw.setSensor(info_.width, info_.height);
  decoder_->imu_keep = size_t(1) << 20;
  imu_.clear();
  next_record_ = 0;
  aedat_.dvs_events = aedat_.sync_events = aedat_.aps_samples = aedat_.imu_samples = 0;
  aedat_.imu_decoded = aedat_.imu_dropped = 0;
  aedat_.out_of_range = aedat_.non_monotonic = aedat_.timestamp_wraps = 0;
  aedat_.checks = decoder_->raw.checks();
}
}  // namespace dvs_driver
