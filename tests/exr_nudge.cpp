// tests/serve_hostile_test.py's tamperer: changes one number of a table's EXR file by the least
// step a float takes, keeping every header attribute (ganzfeld.max_error, the digest, ...) and the
// error channel as they were: what a flipped bit in a cached file, or an edit, looks like to every
// check but ganzfeld.values_digest.
//
//   exr_nudge TABLE.exr INDEX
//
// Float tables only (the cache's default encoding). Exit 0 when written, 1 otherwise.
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfOutputFile.h>

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: exr_nudge TABLE.exr INDEX\n");
    return 1;
  }
  try {
    const std::string path = argv[1];
    const std::size_t index = std::stoul(argv[2]);
    Imf::Header header;
    std::vector<float> value, error;
    int width = 0, height = 0;
    {
      Imf::InputFile in(path.c_str());
      header = in.header();
      const auto window = header.dataWindow();
      width = window.max.x - window.min.x + 1;
      height = window.max.y - window.min.y + 1;
      value.resize(static_cast<std::size_t>(width) * height);
      error.resize(value.size());
      Imf::FrameBuffer frame;
      frame.insert("value",
                   Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(value.data()), sizeof(float), sizeof(float) * width));
      frame.insert("error",
                   Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(error.data()), sizeof(float), sizeof(float) * width));
      in.setFrameBuffer(frame);
      in.readPixels(window.min.y, window.max.y);
    }
    if (index >= value.size())
      throw std::runtime_error("index beyond the table's " + std::to_string(value.size()) + " entries");
    value[index] = std::nextafter(value[index], 2.0f * value[index] + 1.0f);
    Imf::FrameBuffer frame;
    frame.insert("value",
                 Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(value.data()), sizeof(float), sizeof(float) * width));
    frame.insert("error",
                 Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(error.data()), sizeof(float), sizeof(float) * width));
    Imf::OutputFile out(path.c_str(), header);
    out.setFrameBuffer(frame);
    out.writePixels(height);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "exr_nudge: %s\n", e.what());
    return 1;
  }
}
