// Reading throughput and peak memory of the rosbag2 reader on a large synthetic MCAP recording:
// 640x480 frames (rgb8 colour, 32FC1 depth, one CameraInfo each) in 4 MB chunks, uncompressed or
// zstd (level 1), written here (generated, not committed; cached in the temp folder), then opened
// (one scan: the index) and every frame loaded (decoded into an RgbdFrame) in a child process whose
// peak RSS is reported. The file is in the page cache after writing: this measures the reader's CPU
// cost on one core, not the disk.
//
//   build/bench/bench_rosbag2_read [--gb 2] [--compression none|zstd] [--keep] [--max-rss-mb N]
//
// Prints one JSON line: file size, frames, scan and load seconds and MB/s (file bytes per second),
// and the reader's peak RSS in MB. With --max-rss-mb the exit status is 1 when the reader's peak RSS
// is above N (ctest ros2_read_2gb_memory).
#include <sys/resource.h>
#include <sys/wait.h>
#include <zstd.h>

#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include "s3m/rosbag2/bytes.hpp"
#include "s3m/rosbag2/compression.hpp"
#include "s3m/rosbag2/source.hpp"

namespace {
namespace fs = std::filesystem;
using Buf = s3m::rosbag2::ByteBuffer;
using s3m::rosbag2::put_le;
using s3m::rosbag2::put_mcap_record;
using s3m::rosbag2::put_string;

// CDR: each primitive aligned to its size after the 4-byte encapsulation header.
void align(Buf& b, std::size_t n) {
  while ((b.size() - 4) % n) b.push_back(0);
}
void cdr_str(Buf& b, const std::string& s) {
  align(b, 4);
  put_le<std::uint32_t>(b, static_cast<std::uint32_t>(s.size() + 1));
  b.insert(b.end(), s.begin(), s.end());
  b.push_back(0);
}
Buf cdr_header(int sec, unsigned nsec) {
  Buf b = {0, 1, 0, 0};
  put_le<std::int32_t>(b, sec), put_le<std::uint32_t>(b, nsec);
  cdr_str(b, "camera_rgb_optical_frame");
  return b;
}

Buf image(int sec, unsigned nsec, const std::string& encoding, int bytes_per_pixel, int frame) {
  const int w = 640, h = 480;
  Buf b = cdr_header(sec, nsec);
  align(b, 4);
  put_le<std::uint32_t>(b, h), put_le<std::uint32_t>(b, w);
  cdr_str(b, encoding);
  b.push_back(0);
  align(b, 4);
  put_le<std::uint32_t>(b, w * bytes_per_pixel);
  put_le<std::uint32_t>(b, w * h * bytes_per_pixel);
  const std::size_t start = b.size();
  b.resize(start + static_cast<std::size_t>(w) * h * bytes_per_pixel);
  // Smooth shading with sensor-like noise: compresses about as a camera's images do.
  std::uint32_t rng = 12345u + frame;
  if (bytes_per_pixel == 4) {
    for (int i = 0; i < w * h; ++i) {
      rng = rng * 1664525u + 1013904223u;
      const float z = 1.0f + 0.002f * ((i % w + frame) % 900) + 0.001f * ((rng >> 24) & 7);
      std::memcpy(&b[start + 4 * i], &z, 4);
    }
  } else {
    for (int i = 0; i < w * h * 3; ++i) {
      rng = rng * 1664525u + 1013904223u;
      b[start + i] = static_cast<std::uint8_t>((i / 3 % w) / 3 + (i / 3 / w) / 2 + frame + ((rng >> 28) & 7));
    }
  }
  return b;
}

Buf camera_info(int sec, unsigned nsec) {
  Buf b = cdr_header(sec, nsec);
  align(b, 4);
  put_le<std::uint32_t>(b, 480), put_le<std::uint32_t>(b, 640);
  cdr_str(b, "plumb_bob");
  align(b, 4);
  put_le<std::uint32_t>(b, 5);
  align(b, 8);
  for (int i = 0; i < 5; ++i) put_le<double>(b, 0.0);
  for (double k : {525.0, 0.0, 319.5, 0.0, 525.0, 239.5, 0.0, 0.0, 1.0}) put_le<double>(b, k);
  for (int i = 0; i < 9 + 12; ++i) put_le<double>(b, 0.0);
  for (int i = 0; i < 6; ++i) put_le<std::uint32_t>(b, 0);
  b.push_back(0);
  return b;
}

void write_recording(const std::string& path, double gb, bool zstd) {
  std::ofstream out(path, std::ios::binary);
  const Buf magic = {0x89, 'M', 'C', 'A', 'P', 0x30, '\r', '\n'};
  Buf file = magic, h;
  put_string(h, "ros2"), put_string(h, "s3m bench");
  put_mcap_record(file, 0x01, h);
  std::uint32_t data_crc = 0;
  auto flush = [&](Buf& b) {
    data_crc = s3m::rosbag2::crc32({b.data(), b.size()}, data_crc);
    out.write(reinterpret_cast<const char*>(b.data()), static_cast<std::streamsize>(b.size()));
    b.clear();
  };
  flush(file);
  Buf records, chunk;
  const char* topics[] = {"/camera/rgb/image_color", "/camera/depth/image", "/camera/rgb/camera_info"};
  const char* types[] = {"sensor_msgs/msg/Image", "sensor_msgs/msg/Image", "sensor_msgs/msg/CameraInfo"};
  for (std::uint16_t i = 0; i < 3; ++i) {
    Buf s, c;
    put_le<std::uint16_t>(s, i + 1), put_string(s, types[i]), put_string(s, "ros2msg"), put_string(s, "");
    put_le<std::uint16_t>(c, i + 1), put_le<std::uint16_t>(c, i + 1), put_string(c, topics[i]),
        put_string(c, "cdr");
    put_le<std::uint32_t>(c, 0);
    put_mcap_record(records, 0x03, s), put_mcap_record(records, 0x04, c);
  }
  auto end_chunk = [&] {
    Buf compressed;
    if (zstd) {
      compressed.resize(ZSTD_compressBound(records.size()));
      compressed.resize(
          ZSTD_compress(compressed.data(), compressed.size(), records.data(), records.size(), 1));
    }
    const Buf& payload = zstd ? compressed : records;
    Buf c;
    put_le<std::uint64_t>(c, 0), put_le<std::uint64_t>(c, 0), put_le<std::uint64_t>(c, records.size());
    put_le<std::uint32_t>(c, s3m::rosbag2::crc32({records.data(), records.size()}));
    put_string(c, zstd ? "zstd" : "");
    put_le<std::uint64_t>(c, payload.size());
    c.insert(c.end(), payload.begin(), payload.end());
    put_mcap_record(chunk, 0x06, c);
    flush(chunk);
    records.clear();
  };
  const std::size_t frame_bytes = 640 * 480 * 7 + 2000;
  const int frames = static_cast<int>(gb * 1e9 / frame_bytes);
  for (int f = 0; f < frames; ++f) {
    const int sec = 1 + f / 30;
    const unsigned nsec = static_cast<unsigned>((f % 30) * 33333333);
    const std::uint64_t t = static_cast<std::uint64_t>(sec) * 1000000000ull + nsec;
    const Buf msgs[] = {image(sec, nsec, "rgb8", 3, f), image(sec, nsec, "32FC1", 4, f),
                        camera_info(sec, nsec)};
    for (std::uint16_t i = 0; i < 3; ++i) {
      Buf m;
      put_le<std::uint16_t>(m, i + 1), put_le<std::uint32_t>(m, f), put_le<std::uint64_t>(m, t),
          put_le<std::uint64_t>(m, t);
      m.insert(m.end(), msgs[i].begin(), msgs[i].end());
      put_mcap_record(records, 0x05, m);
    }
    if (records.size() > 4000000) end_chunk();
  }
  if (!records.empty()) end_chunk();
  Buf tail, end;
  put_le<std::uint32_t>(end, data_crc);
  put_mcap_record(tail, 0x0F, end);
  put_mcap_record(tail, 0x02, Buf(20, 0));
  tail.insert(tail.end(), magic.begin(), magic.end());
  out.write(reinterpret_cast<const char*>(tail.data()), static_cast<std::streamsize>(tail.size()));
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// The reading half, run in a child process so its peak RSS is the reader's alone.
int read_recording(const std::string& path, const std::string& compression, double max_rss_mb) {
  const double mb = static_cast<double>(fs::file_size(path)) / 1e6;
  auto t0 = std::chrono::steady_clock::now();
  const auto source = s3m::rosbag2::open_rosbag2_source(path, {}, {});
  const double scan_s = seconds_since(t0);
  t0 = std::chrono::steady_clock::now();
  double checksum = 0;
  for (std::size_t i = 0; i < source->size(); ++i) {
    const s3m::RgbdFrame f = source->load(i);
    checksum += f.depth_m.at<float>(0, 0) + f.rgb.at<cv::Vec3b>(0, 0)[0];
  }
  const double load_s = seconds_since(t0);
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  std::printf(
      "{\"compression\": \"%s\", \"file_mb\": %.0f, \"frames\": %zu, \"scan_s\": %.2f, \"scan_mb_per_s\": "
      "%.0f, "
      "\"load_s\": %.2f, \"load_mb_per_s\": %.0f, \"peak_rss_mb\": %.0f, \"checksum\": %.1f}\n",
      compression.c_str(), mb, source->size(), scan_s, mb / scan_s, load_s, mb / load_s,
      usage.ru_maxrss / 1024.0, checksum);
  std::fflush(stdout);  // the child leaves by _exit
  return max_rss_mb > 0 && usage.ru_maxrss / 1024.0 > max_rss_mb ? 1 : 0;
}

}  // namespace

int main(int argc, char** argv) {
  double gb = 2.0;
  std::string compression = "zstd";
  bool keep = false;
  double max_rss_mb = 0;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--gb" && i + 1 < argc)
      gb = std::stod(argv[++i]);
    else if (a == "--compression" && i + 1 < argc)
      compression = argv[++i];
    else if (a == "--keep")
      keep = true;
    else if (a == "--max-rss-mb" && i + 1 < argc)
      max_rss_mb = std::stod(argv[++i]);
    else {
      std::cerr << "usage: bench_rosbag2_read [--gb 2] [--compression none|zstd] [--keep] [--max-rss-mb N]\n";
      return 2;
    }
  }
  const fs::path path =
      fs::temp_directory_path() / ("s3m_bench_rosbag2_" + compression + "_" + std::to_string(gb) + ".mcap");
  try {
    if (!fs::exists(path))
      write_recording(path.string() + ".tmp", gb, compression == "zstd"),
          fs::rename(path.string() + ".tmp", path);
    std::cout.flush();
    const pid_t child = fork();
    if (child == 0) {
      try {
        _exit(read_recording(path.string(), compression, max_rss_mb));
      } catch (const std::exception& e) {
        std::fprintf(stderr, "bench_rosbag2_read: %s\n", e.what());
        _exit(1);
      }
    }
    int status = 0;
    waitpid(child, &status, 0);
    if (!keep) fs::remove(path);
    return WIFEXITED(status) ? WEXITSTATUS(status) : 1;
  } catch (const std::exception& e) {
    std::cerr << "bench_rosbag2_read: " << e.what() << "\n";
    return 1;
  }
}
