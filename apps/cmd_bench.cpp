#include <cstdio>
#include <filesystem>
#include <glm/matrix.hpp>

#include "apps/cli.h"
#include "apps/commands.h"
#include "apps/workloads.h"
#include "engine/scene_file.h"
#include "engine/synth.h"

namespace penumbra::apps {

namespace {

// All instances of a scene as one world-space mesh (the workloads draw one mesh).
engine::Mesh flatten(const engine::Scene& scene) {
  engine::Mesh out;
  for (const engine::Instance& inst : scene.instances) {
    const engine::Mesh& m = scene.meshes[static_cast<size_t>(inst.mesh)];
    const auto base = static_cast<uint32_t>(out.positions.size());
    const glm::mat3 nm = glm::transpose(glm::inverse(glm::mat3(inst.transform)));
    for (size_t i = 0; i < m.positions.size(); ++i) {
      out.positions.push_back(glm::vec3(inst.transform * glm::vec4(m.positions[i], 1.0f)));
      out.normals.push_back(glm::normalize(nm * m.normals[i]));
    }
    for (uint32_t idx : m.indices) out.indices.push_back(base + idx);
  }
  engine::computeBounds(out);
  return out;
}

std::string synthName(long n) {
  if (n % 1000000 == 0) return "synth" + std::to_string(n / 1000000) + "m";
  return "synth" + std::to_string(n);
}

}  // namespace

int runBenchRaster(const BenchRasterArgs& a) {
  std::vector<int> threads = a.threads.empty() ? std::vector<int>{1, 2} : a.threads;
  for (int t : threads)
    if (t < 1 || t > 1024) fail("option --threads", "thread counts must be in [1, 1024], got " + std::to_string(t));
  if (a.frames < 1 || a.frames > 100000) fail("option --frames", "must be in [1, 100000]");
  if (!(a.minSeconds >= 0.0 && a.minSeconds <= 3600.0)) fail("option --min-time", "must be in [0, 3600] seconds");
  std::vector<long> synth = a.synth;
  for (long n : synth)
    if (n < 8 * 64 || n > 64000000) fail("option --synth", "triangle count must be in [512, 64000000]");
  if (synth.empty() && a.meshes.empty()) synth = {1000000, 4000000};
  int maxThreads = 1;
  for (int t : threads) maxThreads = std::max(maxThreads, t);
  const ThreadLimit threadLimit(maxThreads);

  // Load everything first: bad input fails before any run.
  std::vector<std::pair<std::string, engine::Mesh>> meshes;
  for (const std::string& path : a.meshes) {
    engine::Result<engine::Scene> scene = engine::loadScene(path, {.allowOutsidePaths = a.allowOutsidePaths});
    if (!scene) fail(scene.error());
    engine::Mesh m = flatten(*scene);
    if (m.indices.empty()) fail(path, "the scene holds no triangles");
    meshes.emplace_back(std::filesystem::path(path).stem().string(), std::move(m));
  }
  for (long n : synth) meshes.emplace_back(synthName(n), engine::makeSynthMesh(n));

  std::vector<std::string> workloads;
  if (a.workload == "W1" || a.workload == "both") workloads.push_back("W1");
  if (a.workload == "W2" || a.workload == "both") workloads.push_back("W2");
  for (int s : a.msaa)
    if (!raster::isSampleCount(s)) fail("option --msaa", "sample counts must be 1, 2, 4 or 8, got " + std::to_string(s));
  const int total = static_cast<int>(meshes.size() * (workloads.size() + a.msaa.size()) * threads.size());
  Progress progress("bench raster");
  int index = 0;
  for (const auto& [name, mesh] : meshes)
    for (const std::string& w : workloads)
      for (int t : threads) {
        progress.step(++index, total, name + " " + w + " threads=" + std::to_string(t));
        const WorkloadResult r = runWorkload(w, name, mesh, t, a.frames, a.minSeconds);
        std::printf("%s\n", a.json ? r.json().c_str() : r.line().c_str());
        std::fflush(stdout);
      }
  // Multisampled W2: the cost at each sample count, and the edge error (once per mesh and count).
  for (const auto& [name, mesh] : meshes)
    for (int s : a.msaa) {
      const EdgeError e = w2EdgeError(mesh, s, 240, 135, maxThreads);
      for (int t : threads) {
        progress.step(++index, total, name + " W2 msaa " + std::to_string(s) + " threads=" + std::to_string(t));
        WorkloadResult r = s == 1 ? runWorkload("W2", name, mesh, t, a.frames, a.minSeconds)
                                  : runW2Multisample(name, mesh, t, s, a.frames, a.minSeconds);
        r.edgeRmse = e.rmse;
        r.edgePixels = e.edgePixels;
        std::printf("%s\n", a.json ? r.json().c_str() : r.line().c_str());
        std::fflush(stdout);
      }
    }
  progress.done();
  return 0;
}

}  // namespace penumbra::apps
