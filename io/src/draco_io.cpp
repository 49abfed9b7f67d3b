// Draco (.drc) and glTF 2.0 binary (.glb, KHR_draco_mesh_compression) through Draco's own
// library: draco::Encoder for .drc, draco::GltfEncoder for .glb (Debian's libdraco-dev is
// built with DRACO_TRANSCODER_SUPPORTED, which provides it), draco::Decoder to read .drc.
//
// Vertices are split between CAD faces: a vertex carries one normal and one face id, and
// both change across a CAD edge (the normal is smooth inside a face and creased at its
// boundary, which is how a viewer should shade a CAD part). Quantization maps every copy
// of a split vertex to the same grid point, so the reader merges them back exactly.
#include "draco_io.h"

#include <draco/compression/decode.h>
#include <draco/compression/encode.h>
#include <draco/io/gltf_encoder.h>
#include <draco/mesh/mesh.h>
#include <draco/metadata/geometry_metadata.h>
#include <draco/scene/scene.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <csignal>
#include <map>
#include <memory>
#include <unordered_map>

namespace uvmesh::io::detail {

namespace {

using surface::NodeId;
using surface::SurfaceMesh;

constexpr const char* kFaceIdName = "face_id";

// The triangles of one output mesh with their vertices split per CAD face.
struct SplitMesh {
  std::vector<NodeId> node;              ///< per split vertex: the mesh node
  std::vector<geom::Id> face;            ///< per split vertex: its CAD face
  std::vector<geom::Vec3> normal;        ///< per split vertex: unit normal within its face
  std::vector<std::array<int, 3>> tris;  ///< in split-vertex indices
};

SplitMesh split_by_face(const SurfaceMesh& m, const std::vector<std::size_t>& triangles) {
  SplitMesh s;
  // (face, node) -> split vertex; triangles of one face are usually contiguous, so a
  // per-face map is rebuilt rarely.
  std::map<std::pair<geom::Id, NodeId>, int> index;
  for (std::size_t t : triangles) {
    const auto& tri = m.triangles[t];
    const geom::Id f = m.triangle_face[t];
    std::array<int, 3> out{};
    for (int k = 0; k < 3; ++k) {
      auto [it, fresh] = index.emplace(std::pair{f, tri[k]}, static_cast<int>(s.node.size()));
      if (fresh) {
        s.node.push_back(tri[k]);
        s.face.push_back(f);
        s.normal.push_back(geom::Vec3(0.0));
      }
      out[k] = it->second;
    }
    // Area-weighted corner normals: the unnormalized cross product weighs by area.
    const geom::Vec3& a = m.points[static_cast<std::size_t>(tri[0])];
    const geom::Vec3 n = glm::cross(m.points[static_cast<std::size_t>(tri[1])] - a,
                                    m.points[static_cast<std::size_t>(tri[2])] - a);
    for (int k = 0; k < 3; ++k) s.normal[static_cast<std::size_t>(out[k])] += n;
    s.tris.push_back(out);
  }
  for (geom::Vec3& n : s.normal) {
    const double len = glm::length(n);
    n = len > 0.0 ? n / len : geom::Vec3(0.0, 0.0, 1.0);
  }
  return s;
}

int add_float_attribute(draco::Mesh& dm, draco::GeometryAttribute::Type type, std::size_t n,
                        const auto& value_of) {
  draco::GeometryAttribute ga;
  ga.Init(type, nullptr, 3, draco::DT_FLOAT32, false, sizeof(float) * 3, 0);
  const int id = dm.AddAttribute(ga, true, static_cast<unsigned>(n));
  for (std::size_t i = 0; i < n; ++i) {
    const geom::Vec3 v = value_of(i);
    const float f[3] = {static_cast<float>(v.x), static_cast<float>(v.y), static_cast<float>(v.z)};
    dm.attribute(id)->SetAttributeValue(draco::AttributeValueIndex(static_cast<unsigned>(i)), f);
  }
  return id;
}

std::unique_ptr<draco::Mesh> to_draco(const SurfaceMesh& m, const SplitMesh& s, bool face_ids) {
  auto dm = std::make_unique<draco::Mesh>();
  const std::size_t n = s.node.size();
  dm->set_num_points(static_cast<unsigned>(n));
  add_float_attribute(*dm, draco::GeometryAttribute::POSITION, n,
                      [&](std::size_t i) { return m.points[static_cast<std::size_t>(s.node[i])]; });
  add_float_attribute(*dm, draco::GeometryAttribute::NORMAL, n,
                      [&](std::size_t i) { return s.normal[i]; });
  if (face_ids) {
    draco::GeometryAttribute ga;
    ga.Init(draco::GeometryAttribute::GENERIC, nullptr, 1, draco::DT_INT32, false,
            sizeof(std::int32_t), 0);
    const int id = dm->AddAttribute(ga, true, static_cast<unsigned>(n));
    for (std::size_t i = 0; i < n; ++i) {
      const std::int32_t f = s.face[i];
      dm->attribute(id)->SetAttributeValue(draco::AttributeValueIndex(static_cast<unsigned>(i)),
                                           &f);
    }
    // The name travels as attribute metadata, which draco_decoder and our reader keep.
    auto md = std::make_unique<draco::AttributeMetadata>();
    md->AddEntryString("name", kFaceIdName);
    dm->AddAttributeMetadata(id, std::move(md));
  }
  for (const auto& t : s.tris)
    dm->AddFace({draco::PointIndex(static_cast<unsigned>(t[0])),
                 draco::PointIndex(static_cast<unsigned>(t[1])),
                 draco::PointIndex(static_cast<unsigned>(t[2]))});
  return dm;
}

std::vector<std::size_t> all_triangles(const SurfaceMesh& m) {
  std::vector<std::size_t> all(m.triangles.size());
  for (std::size_t t = 0; t < all.size(); ++t) all[t] = t;
  return all;
}

}  // namespace

std::string encode_drc(const SurfaceMesh& m, const WriteOptions& opts, std::vector<char>& bytes) {
  if (m.triangles.empty()) return "Draco needs at least one triangle";
  const std::unique_ptr<draco::Mesh> dm = to_draco(m, split_by_face(m, all_triangles(m)), true);
  draco::Encoder enc;
  enc.SetAttributeQuantization(draco::GeometryAttribute::POSITION, opts.draco_bits);
  enc.SetAttributeQuantization(draco::GeometryAttribute::NORMAL, opts.draco_normal_bits);
  const int speed = 10 - opts.draco_level;
  enc.SetSpeedOptions(speed, speed);
  enc.SetEncodingMethod(draco::MESH_EDGEBREAKER_ENCODING);
  draco::EncoderBuffer buf;
  const draco::Status st = enc.EncodeMeshToBuffer(*dm, &buf);
  if (!st.ok()) return "Draco encoding failed: " + st.error_msg_string();
  bytes.assign(buf.data(), buf.data() + buf.size());
  return "";
}

std::string encode_glb(const SurfaceMesh& m, const geom::Model* model, const WriteOptions& opts,
                       std::vector<char>& bytes) {
  if (m.triangles.empty()) return "glTF needs at least one triangle";
  // Groups of triangles, one glTF mesh each, with their names.
  std::map<std::size_t, std::vector<std::size_t>> groups;
  std::map<std::size_t, std::string> names;
  if (opts.glb_groups == GlbGroups::Face || !model || model->solids.empty()) {
    for (std::size_t t = 0; t < m.triangles.size(); ++t)
      groups[static_cast<std::size_t>(m.triangle_face[t])].push_back(t);
    for (const auto& [f, tris] : groups) {
      const bool named = model && f < model->faces.size() && !model->faces[f].name.empty();
      names[f] = named ? model->faces[f].name : "face_" + std::to_string(f);
    }
  } else {
    // A face belongs to the first solid whose shells list it; loose faces form one more
    // group after the solids.
    const std::size_t loose = model->solids.size();
    std::vector<std::size_t> solid_of(model->faces.size(), loose);
    for (std::size_t s = model->solids.size(); s-- > 0;)
      for (geom::Id sh : model->solids[s].shells)
        if (sh >= 0 && static_cast<std::size_t>(sh) < model->shells.size())
          for (geom::Id f : model->shells[static_cast<std::size_t>(sh)].faces)
            if (f >= 0 && static_cast<std::size_t>(f) < solid_of.size())
              solid_of[static_cast<std::size_t>(f)] = s;
    for (std::size_t t = 0; t < m.triangles.size(); ++t) {
      const auto f = static_cast<std::size_t>(m.triangle_face[t]);
      groups[f < solid_of.size() ? solid_of[f] : loose].push_back(t);
    }
    for (const auto& [s, tris] : groups)
      names[s] = s == loose                      ? "loose_faces"
                 : model->solids[s].name.empty() ? "solid_" + std::to_string(s + 1)
                                                 : model->solids[s].name;
  }

  draco::Scene scene;
  scene.GetMaterialLibrary().MutableMaterial(0)->SetName("uvmesh");
  draco::DracoCompressionOptions copt;
  copt.compression_level = opts.draco_level;
  copt.quantization_position.SetQuantizationBits(opts.draco_bits);
  copt.quantization_bits_normal = opts.draco_normal_bits;
  for (const auto& [key, tris] : groups) {
    std::unique_ptr<draco::Mesh> dm = to_draco(m, split_by_face(m, tris), false);
    dm->SetName(names[key]);
    dm->SetCompressionEnabled(true);
    dm->SetCompressionOptions(copt);
    const draco::MeshIndex mi = scene.AddMesh(std::move(dm));
    const draco::MeshGroupIndex gi = scene.AddMeshGroup();
    scene.GetMeshGroup(gi)->SetName(names[key]);
    scene.GetMeshGroup(gi)->AddMeshInstance(draco::MeshGroup::MeshInstance(mi, 0));
    const draco::SceneNodeIndex ni = scene.AddNode();
    scene.GetNode(ni)->SetName(names[key]);
    scene.GetNode(ni)->SetMeshGroupIndex(gi);
    scene.AddRootNodeIndex(ni);
  }
  draco::GltfEncoder enc;
  draco::EncoderBuffer buf;
  const draco::Status st = enc.EncodeToBuffer(scene, &buf);
  if (!st.ok()) return "glTF encoding failed: " + st.error_msg_string();
  bytes.assign(buf.data(), buf.data() + buf.size());
  return "";
}

namespace {

// Draco's decoder (1.5.5) is not hardened against malformed input: some corrupt files
// make it crash or loop instead of returning an error status. So a file is decoded first
// in a child process (fork: the child runs only this thread, and glibc keeps malloc usable
// across fork); only when the child finished cleanly is it decoded here. "" or the reason.
std::string probe_decode(const char* data, std::size_t size) {
  const pid_t pid = ::fork();
  if (pid < 0) return "";  // cannot probe: decode directly, as without the probe
  if (pid == 0) {
    const rlimit no_core{0, 0};
    ::setrlimit(RLIMIT_CORE, &no_core);
    draco::DecoderBuffer db;
    db.Init(data, size);
    draco::Decoder dec;
    const bool ok = dec.DecodeMeshFromBuffer(&db).ok();
    ::_exit(ok ? 0 : 1);
  }
  int status = 0;
  // Bounded wait: a decoder stuck in a loop is an error too, not a hang.
  for (int ms = 0; ms < 120000; ++ms) {
    const pid_t w = ::waitpid(pid, &status, WNOHANG);
    if (w == pid) {
      if (WIFSIGNALED(status))
        return "Draco's decoder crashed on the file (signal " + std::to_string(WTERMSIG(status)) +
               "): corrupt data";
      return "";  // exit 1 is a clean error status: the real decode reports it
    }
    if (w < 0) return "";
    ::usleep(1000);
  }
  ::kill(pid, SIGKILL);
  ::waitpid(pid, &status, 0);
  return "Draco's decoder did not finish within 120 s: corrupt data";
}

}  // namespace

std::string decode_drc(const char* data, std::size_t size, SurfaceMesh& m, bool& has_face_ids) {
  if (std::string why = probe_decode(data, size); !why.empty()) return why;
  draco::DecoderBuffer db;
  db.Init(data, size);
  draco::Decoder dec;
  auto sor = dec.DecodeMeshFromBuffer(&db);
  if (!sor.ok()) return "not a Draco mesh, or a corrupt one: " + sor.status().error_msg_string();
  const std::unique_ptr<draco::Mesh> dm = std::move(sor).value();
  const draco::PointAttribute* pos = dm->GetNamedAttribute(draco::GeometryAttribute::POSITION);
  if (!pos || pos->num_components() < 3) return "the Draco mesh has no 3D positions";
  const draco::PointAttribute* fid = nullptr;
  if (const draco::AttributeMetadata* md =
          dm->GetAttributeMetadataByStringEntry("name", kFaceIdName))
    fid = dm->GetAttributeByUniqueId(md->att_unique_id());
  has_face_ids = fid != nullptr;

  // Merge points by decoded position value (see the file comment). Values are read
  // through ConvertValue with the component count asked for, so that an attribute of
  // another type or width (a corrupt or foreign file) cannot write past the buffers.
  std::map<std::array<float, 3>, NodeId> node_of;
  std::vector<NodeId> node(dm->num_points());
  for (draco::PointIndex p(0); p < dm->num_points(); ++p) {
    std::array<float, 3> v{};
    if (!pos->ConvertValue<float>(pos->mapped_index(p), 3, v.data()))
      return "point " + std::to_string(p.value()) + " has no readable position";
    if (!std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2]))
      return "point " + std::to_string(p.value()) + " has a non-finite position";
    auto [it, fresh] = node_of.emplace(v, static_cast<NodeId>(m.points.size()));
    if (fresh) m.points.emplace_back(v[0], v[1], v[2]);
    node[p.value()] = it->second;
  }
  for (draco::FaceIndex f(0); f < dm->num_faces(); ++f) {
    const draco::Mesh::Face& face = dm->face(f);
    for (int k = 0; k < 3; ++k)
      if (face[k].value() >= dm->num_points())
        return "face " + std::to_string(f.value()) + " refers to point " +
               std::to_string(face[k].value()) + " of " + std::to_string(dm->num_points());
    m.triangles.push_back({node[face[0].value()], node[face[1].value()], node[face[2].value()]});
    std::int32_t id = 0;
    if (fid && !fid->ConvertValue<std::int32_t>(fid->mapped_index(face[0]), 1, &id)) id = 0;
    m.triangle_face.push_back(std::max<std::int32_t>(id, 0));
  }
  return "";
}

}  // namespace uvmesh::io::detail
