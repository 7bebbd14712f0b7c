#include "playback/writer.h"

#include "hapstate/playback.h"

#include "util/error.h"
#include "util/grid_direction.h"
#include "util/hash.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <string>

namespace hapstate::playback {
namespace {

std::uint64_t align_up(std::uint64_t n) { return (n + kAlignment - 1) / kAlignment * kAlignment; }

// An output file written with pwrite at explicit offsets, hashing each section as it goes.
class OutFile {
 public:
  OutFile(std::filesystem::path path) : path_(std::move(path)) {
    fd_ = ::open(path_.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd_ < 0) fail("cannot create");
  }
  ~OutFile() {
    if (fd_ >= 0) ::close(fd_);
  }
  void write_at(std::uint64_t offset, const void* data, std::size_t bytes) {
    const char* p = static_cast<const char*>(data);
    while (bytes > 0) {
      const ssize_t n = ::pwrite(fd_, p, bytes, static_cast<off_t>(offset));
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) fail("cannot write");
      p += n;
      offset += static_cast<std::uint64_t>(n);
      bytes -= static_cast<std::size_t>(n);
    }
  }
  void finish(std::uint64_t size) {
    if (::ftruncate(fd_, static_cast<off_t>(size)) != 0) fail("cannot size");
    if (::fsync(fd_) != 0) fail("cannot fsync");
    if (::close(fd_) != 0) {
      fd_ = -1;
      fail("cannot close");
    }
    fd_ = -1;
  }
  // Writing fails only for the environment's reasons (disk full, permissions, I/O error).
  [[noreturn]] void fail(const char* what) const {
    throw EnvironmentError(path_.string() + ": " + what + ": " + os_error_text(errno));
  }

 private:
  std::filesystem::path path_;
  int fd_ = -1;
};

// Fills in the header's size and both checksums for `table` (kSectionCount entries).
void seal_header(FileHeader* header, const SectionEntry* table, std::uint64_t file_size) {
  header->file_size = file_size;
  header->section_table_checksum =
      content_hash(std::as_bytes(std::span<const SectionEntry>(table, kSectionCount))).value;
  header->header_checksum =
      content_hash(std::as_bytes(std::span(header, 1)).first(offsetof(FileHeader, header_checksum)))
          .value;
}

// Renames the finished `tmp` over `file` and makes the rename durable (fsync of the directory).
void replace_file(const std::filesystem::path& tmp, const std::filesystem::path& file) {
  std::filesystem::rename(tmp, file);
  const int dir = ::open(file.parent_path().empty() ? "." : file.parent_path().c_str(),
                         O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dir >= 0) {
    ::fsync(dir);
    ::close(dir);
  }
}

std::filesystem::path temporary_beside(const std::filesystem::path& file) {
  std::filesystem::path tmp = file;
  tmp += ".tmp-" + std::to_string(::getpid());
  return tmp;
}

template <class T>
std::span<const std::byte> bytes_of(const std::vector<T>& v) {
  return std::as_bytes(std::span<const T>(v));
}

void check_content(const Content& c, const std::filesystem::path& file) {
  const std::size_t n = c.config_checkpoint.size();
  const std::size_t points =
      static_cast<std::size_t>(c.meta.dims[0]) * c.meta.dims[1] * c.meta.dims[2];
  auto bad = [&](const std::string& what) {
    throw InputError(file.string() + ": cannot write a playback file: " + what);
  };
  for (int a = 0; a < 3; ++a) {
    if (c.meta.dims[a] < 1) bad("the grid needs at least 1 check-point along every axis");
    if (!(c.meta.spacing[a] > 0)) bad("grid spacing must be positive");
  }
  if (c.checkpoints.size() != 2 * points) bad("check-point table size");
  if (!c.midpoint_displacement_mask.empty() &&
      (c.midpoint_displacement_mask.size() != n || !c.midpoint_displacements))
    bad("midpoint displacement mask size, or no midpoint displacements for it");
  if (c.config_level.size() != n || c.config_zero.size() != n || c.force.size() != 3 * n ||
      c.stiffness.size() != 9 * n || c.transitions.size() != grid::kDirections * n)
    bad("configuration table sizes");
  if (c.reference.size() != 3 * c.view_nodes.size() || c.triangles.size() % 3 != 0)
    bad("view node table sizes");
  if (n == 0) bad("no configurations");
  if (c.meta.rest_configuration < 0 || static_cast<std::size_t>(c.meta.rest_configuration) >= n)
    bad("no rest configuration");
  if (!c.displacements) bad("no displacement source");
  const bool contact = c.meta.probe_mode == static_cast<std::int32_t>(ProbeModeCode::kContact);
  if (c.clearance.size() != (contact ? 4 * points : 0)) bad("clearance table size");
  if (c.onset.size() != (contact ? n : 0)) bad("onset table size");
  if (const char* problem = onset_lists_problem(
          c.onset_triangles.data(), c.onset_triangles.size(), c.onset_cells.data(),
          c.onset_cells.size(), c.onset_triangle_list.data(), c.onset_triangle_list.size(),
          std::int64_t(points), c.meta.contact_radius))
    bad(problem);
  if (!c.midpoint_force.empty() && c.midpoint_force.size() != 3 * kMidpointDirections * n)
    bad("midpoint force table size");
  for (double v : c.midpoint_force)
    if (std::isinf(v)) bad("a midpoint force is infinite");
  if (!c.midpoint_stiffness.empty() &&
      (c.midpoint_force.empty() || c.midpoint_stiffness.size() != 9 * kMidpointDirections * n))
    bad("midpoint stiffness table size");
  for (double v : c.midpoint_stiffness)
    if (std::isinf(v)) bad("a midpoint stiffness is infinite");
  const std::size_t refined = c.refined_points.size() / (12 * kRefinedPoints);
  const std::size_t eighth = c.eighth_points.size() / (12 * kEighthPoints);
  const std::size_t sixteenth = c.sixteenth_points.size() / (12 * kSixteenthPoints);
  if (c.refined_points.size() != 12 * kRefinedPoints * refined ||
      c.eighth_points.size() != 12 * kEighthPoints * eighth ||
      c.sixteenth_points.size() != 12 * kSixteenthPoints * sixteenth ||
      (sixteenth > 0 && eighth == 0) ||
      (!c.refined_cells.empty() && c.refined_cells.size() != kRefinedCellInts * n) ||
      (!c.refined_cells.empty() && c.midpoint_stiffness.empty()) ||
      (refined > 0 && c.refined_cells.empty()) || (eighth > 0 && refined == 0))
    bad("refined cell table sizes (refined cells need the midpoint stiffness)");
  for (std::size_t k = 0; k < c.refined_cells.size(); k += kRefinedCellInts)
    if (c.refined_cells[k] < -1 || c.refined_cells[k] >= static_cast<std::int32_t>(refined) ||
        c.refined_cells[k + 2] < -1 ||
        c.refined_cells[k + 2] >= static_cast<std::int32_t>(eighth) ||
        (c.refined_cells[k + 2] >= 0 && c.refined_cells[k] < 0) || c.refined_cells[k + 4] < -1 ||
        c.refined_cells[k + 4] >= static_cast<std::int32_t>(sixteenth) ||
        (c.refined_cells[k + 4] >= 0 && c.refined_cells[k + 2] < 0))
      bad("a refined cell index is out of range");
  for (double v : c.refined_points)
    if (std::isinf(v)) bad("a refined point's force or stiffness is infinite");
  for (double v : c.eighth_points)
    if (std::isinf(v)) bad("an eighth-spacing point's force or stiffness is infinite");
  for (double v : c.sixteenth_points)
    if (std::isinf(v)) bad("a sixteenth-spacing point's force or stiffness is infinite");
}

// The clamp limits of the bubbles' corrections (edge, face, cell; N per component).
std::array<double, 3> bubble_limits(const Content& c) {
  std::array<double, 3> limit{};
  if (c.midpoint_force.empty()) return limit;
  const std::size_t n = c.config_checkpoint.size();
  double k_max = 0.0;
  for (double k : c.stiffness) k_max = std::max(k_max, std::abs(k));
  double reach[3] = {0, 0, 0};  // per kind: the largest |m - f_source| + |f_target - f_source|
  for (std::size_t src = 0; src < n; ++src)
    for (int d = 0; d < kMidpointDirections; ++d) {
      const std::int32_t tgt =
          c.transitions[grid::kDirections * src + grid::direction_index(kMidpointOffsets[d][0],
                                                                        kMidpointOffsets[d][1],
                                                                        kMidpointOffsets[d][2])];
      const double* m = &c.midpoint_force[3 * (kMidpointDirections * src + d)];
      if (tgt < 0 || std::isnan(m[0]) || std::isnan(m[1]) || std::isnan(m[2])) continue;
      const int kind = d < 3 ? 0 : (d < 6 ? 1 : 2);
      for (int r = 0; r < 3; ++r)
        reach[kind] =
            std::max(reach[kind], std::abs(m[r] - c.force[3 * src + r]) +
                                      std::abs(c.force[3 * tgt + r] - c.force[3 * src + r]));
    }
  // What the interpolant can differ from a corner by at the bubble's point, generously: the
  // value differences above, the derivative terms (a quarter spacing times the stiffness per
  // axis crossed), and the bubbles fitted before (an edge's is 1/2 at a face centre, 1/4 at the
  // cell centre; a face's 1/2 there).
  const double* h = c.meta.spacing;
  const double hsum = h[0] + h[1] + h[2];
  limit[0] = reach[0] + 0.25 * std::max({h[0], h[1], h[2]}) * k_max;
  limit[1] = reach[1] + 0.5 * hsum * k_max + 2.0 * limit[0];
  limit[2] = reach[2] + 0.75 * hsum * k_max + 3.0 * limit[0] + 3.0 * limit[1];
  return limit;
}

// The clamp limit of a midpoint's stiffness entries (Meta::stiffness_limit): the largest |entry|
// of any stored stiffness, configurations and midpoints; 0 without midpoint stiffness.
double stiffness_limit(const Content& c) {
  double limit = 0.0;
  if (c.midpoint_stiffness.empty()) return limit;
  for (double k : c.stiffness) limit = std::max(limit, std::abs(k));
  for (double k : c.midpoint_stiffness)
    if (std::isfinite(k)) limit = std::max(limit, std::abs(k));
  for (const std::vector<double>* points :
       {&c.refined_points, &c.eighth_points, &c.sixteenth_points})
    for (std::size_t k = 0; k < points->size(); ++k)
      if (k % 12 >= 3 && std::isfinite((*points)[k]))
        limit = std::max(limit, std::abs((*points)[k]));
  return limit;
}

}  // namespace

double force_change_bound(const Content& c) {
  const std::size_t n = c.config_checkpoint.size();
  double slope = 0.0, stiffness = 0.0;
  for (std::size_t a = 0; a < n; ++a) {
    double k2 = 0;
    for (int r = 0; r < 9; ++r) k2 += c.stiffness[9 * a + r] * c.stiffness[9 * a + r];
    stiffness = std::max(stiffness, std::sqrt(k2));
    const auto ia = grid_point_ijk(c.meta, c.config_checkpoint[a]);
    for (int di = -1; di <= 1; ++di)
      for (int dj = -1; dj <= 1; ++dj)
        for (int dk = -1; dk <= 1; ++dk) {
          const std::int32_t g = grid_point_index(c.meta, {ia[0] + di, ia[1] + dj, ia[2] + dk});
          if ((di == 0 && dj == 0 && dk == 0) || g < 0) continue;
          const double dist =
              std::sqrt(std::pow(di * c.meta.spacing[0], 2) + std::pow(dj * c.meta.spacing[1], 2) +
                        std::pow(dk * c.meta.spacing[2], 2));
          for (int b = c.checkpoints[2 * g]; b < c.checkpoints[2 * g] + c.checkpoints[2 * g + 1];
               ++b) {
            double d2 = 0;
            for (int r = 0; r < 3; ++r) d2 += std::pow(c.force[3 * b + r] - c.force[3 * a + r], 2);
            slope = std::max(slope, std::sqrt(d2) / dist);
          }
        }
  }
  const double hmax = std::max({c.meta.spacing[0], c.meta.spacing[1], c.meta.spacing[2]});
  const double hmin = std::min({c.meta.spacing[0], c.meta.spacing[1], c.meta.spacing[2]});
  // The bubbles' slope: each correction is clamped to its kind's limit per component, and a
  // bubble's gradient is at most 5.4 per unit of the cell position (3.08 along an axis it
  // peaks on, 1.5 across; the trilinear hat's 2 and 1).
  const double* limit = c.meta.bubble_limit;
  const double bubbles =
      std::sqrt(3.0) * 5.4 * (12.0 * limit[0] + 6.0 * limit[1] + limit[2]) / hmin;
  // The corners' cubic (cross derivatives at most 2 K / h_min): along an axis at most 1.5 L
  // (values) + K (slopes along it) + 1.5 rho K (across) + rho K (cross terms with it) +
  // 0.375 rho^2 K (the third) <= 4 rho^2 (L + K), rho = h_max / h_min; sqrt(3) times that along
  // any direction.
  const double rho = hmax / hmin;
  const double corners = 4.0 * std::sqrt(3.0) * (slope + stiffness) * rho * rho;
  if (c.midpoint_stiffness.empty()) return corners + bubbles;
  // Hermite on the half-spacing cells, with the lattice's data: a lattice point's value is the
  // corners' interpolant there plus a correction of at most the bubble limit per component, so
  // two points differ by at most corners x their distance plus 2 sqrt(3) max(limit) (their
  // distance is at least h_min / 2): slope L'; its gradient is a clamped stored stiffness
  // (Frobenius norm <= 3 stiffness_limit) or that interpolant's: K'. A half cell's cross
  // derivatives come from parabolas through 3 gradients (at most 4 K' / h'_min, h' = h / 2), so
  // with rho = h_max / h_min its derivative along an axis is at most 1.5 L' (values) + K' (slopes
  // along it) + 1.5 rho K' (across) + 2 rho K' (cross terms with it) + 0.75 rho^2 K' (the third)
  // <= 5.25 rho^2 (L' + K'); along any direction sqrt(3) times that.
  const double lambda = std::max({limit[0], limit[1], limit[2]});
  const double lattice_slope = corners + 4.0 * std::sqrt(3.0) * lambda / hmin;
  const double lattice_stiffness = std::max(3.0 * c.meta.stiffness_limit, corners);
  const double half_cells = 5.25 * std::sqrt(3.0) * (lattice_slope + lattice_stiffness) * rho * rho;
  if (c.refined_points.empty()) return std::max(corners + bubbles, half_cells);
  // Refined cells: Hermite on the quarter-spacing cells, whose points are the half cells'
  // interpolant there (slope at most half_cells) plus a correction of at most the largest limit
  // per component, at least h_min / 4 apart, with a gradient that is a clamped stored stiffness
  // or that interpolant's: the same argument one level down (at a constrained point the cross
  // derivatives are the half cells' own, bounded as theirs).
  const double quarter_slope = half_cells + 8.0 * std::sqrt(3.0) * lambda / hmin;
  const double quarter_stiffness = std::max(3.0 * c.meta.stiffness_limit, half_cells);
  const double quarter_cells =
      5.25 * std::sqrt(3.0) * (quarter_slope + quarter_stiffness) * rho * rho;
  if (c.eighth_points.empty()) return std::max({corners + bubbles, half_cells, quarter_cells});
  // Eighth-spacing lattices: the same argument once more, from the quarter cells' interpolant
  // (slope at most quarter_cells), points at least h_min / 8 apart. A solved point's gradient
  // entry limited by the values around it (the cursor's limit_eighth_slope) lies within 2.1 times
  // the largest difference quotient of the values there, at most eighth_slope: 3 x 2.1 for the
  // Frobenius norm.
  const double eighth_slope = quarter_cells + 16.0 * std::sqrt(3.0) * lambda / hmin;
  const double eighth_stiffness =
      std::max({3.0 * c.meta.stiffness_limit, quarter_cells, 6.3 * eighth_slope});
  const double eighth_cells = 5.25 * std::sqrt(3.0) * (eighth_slope + eighth_stiffness) * rho * rho;
  if (c.sixteenth_points.empty())
    return std::max({corners + bubbles, half_cells, quarter_cells, eighth_cells});
  // Sixteenth-spacing lattices: once more, from the eighth cells' interpolant, points at least
  // h_min / 16 apart, their slopes limited as the eighth-spacing points' are.
  const double sixteenth_slope = eighth_cells + 32.0 * std::sqrt(3.0) * lambda / hmin;
  const double sixteenth_stiffness =
      std::max({3.0 * c.meta.stiffness_limit, eighth_cells, 6.3 * sixteenth_slope});
  const double sixteenth_cells =
      5.25 * std::sqrt(3.0) * (sixteenth_slope + sixteenth_stiffness) * rho * rho;
  return std::max({corners + bubbles, half_cells, quarter_cells, eighth_cells, sixteenth_cells});
}

namespace {

// A section as write_file lays it out: its bytes in memory, or streamed one configuration at a
// time (the displacements and their slopes).
struct PendingSection {
  SectionId id;
  std::uint32_t element_bytes;
  std::span<const std::byte> data;  // empty for the streamed sections
  std::uint64_t bytes;
  // A streamed section: fills the floats of one configuration.
  const std::function<void(std::int32_t, std::span<float>)>* stream = nullptr;
  std::uint64_t row_floats = 0;
};

// Writes the sections from `offset` on, each 64-byte aligned, into `out` (n configurations for
// the streamed ones), and their table entries with checksums into `table`; returns the end.
std::uint64_t write_sections(OutFile& out, const PendingSection (&pending)[kSectionCount],
                             std::size_t n, std::uint64_t offset,
                             SectionEntry (&table)[kSectionCount]) {
  for (int s = 0; s < kSectionCount; ++s) {
    const PendingSection& p = pending[s];
    table[s] = {static_cast<std::uint32_t>(p.id), p.element_bytes, offset, p.bytes, 0};
    if (!p.stream) {
      out.write_at(offset, p.data.data(), p.data.size());
      table[s].checksum = content_hash(p.data).value;
    } else {
      ContentHasher hasher;
      std::vector<float> row(p.row_floats);
      for (std::size_t k = 0; k < n && p.row_floats > 0; ++k) {
        std::fill(row.begin(), row.end(), 0.0f);
        (*p.stream)(static_cast<std::int32_t>(k), row);
        out.write_at(offset + 4 * p.row_floats * k, row.data(), 4 * p.row_floats);
        hasher.update(std::as_bytes(std::span<const float>(row)));
      }
      table[s].checksum = hasher.value().value;
    }
    offset = align_up(offset + p.bytes);
  }
  return offset;
}

// The section table at table_offset and the sealed header at 0, for a file of `end` bytes.
void write_header_and_table(OutFile& out, const SectionEntry (&table)[kSectionCount],
                            std::uint64_t table_offset, std::uint64_t end) {
  FileHeader header{};
  std::memcpy(header.magic, kMagic, sizeof(kMagic));
  header.version = kVersion;
  header.header_bytes = sizeof(FileHeader);
  header.section_table_offset = table_offset;
  header.section_count = kSectionCount;
  header.section_entry_bytes = sizeof(SectionEntry);
  seal_header(&header, table, end);
  out.write_at(table_offset, table, sizeof(table));
  out.write_at(0, &header, sizeof(header));
}

}  // namespace

void write_file(Content c, const std::filesystem::path& file) {
  check_content(c, file);
  const std::size_t n = c.config_checkpoint.size();
  const std::size_t v = c.view_nodes.size();
  c.meta.num_configurations = static_cast<std::int32_t>(n);
  c.meta.num_view_nodes = static_cast<std::int32_t>(v);
  c.meta.num_triangles = static_cast<std::int32_t>(c.triangles.size() / 3);
  const std::array<double, 3> limit = bubble_limits(c);
  std::copy(limit.begin(), limit.end(), c.meta.bubble_limit);
  c.meta.stiffness_limit = stiffness_limit(c);
  c.meta.force_change_bound = force_change_bound(c);
  c.meta.has_displacement_slopes = c.displacement_slopes ? 1 : 0;
  const std::uint64_t slope_floats = c.displacement_slopes ? 9 * v : 0;
  const std::uint64_t midpoint_floats =
      c.midpoint_displacement_mask.empty() ? 0 : 12 * kMidpointDirections * v;

  const std::vector<Meta> meta{c.meta};
  const PendingSection pending[kSectionCount] = {
      {SectionId::kMeta, sizeof(Meta), bytes_of(meta), sizeof(Meta)},
      {SectionId::kCheckpoints, 8, bytes_of(c.checkpoints), 4 * c.checkpoints.size()},
      {SectionId::kConfigCheckpoint, 4, bytes_of(c.config_checkpoint), 4 * n},
      {SectionId::kConfigLevel, 4, bytes_of(c.config_level), 4 * n},
      {SectionId::kConfigZero, 4, bytes_of(c.config_zero), 4 * n},
      {SectionId::kForce, 24, bytes_of(c.force), 24 * n},
      {SectionId::kStiffness, 72, bytes_of(c.stiffness), 72 * n},
      {SectionId::kTransitions, 104, bytes_of(c.transitions), 104 * n},
      {SectionId::kViewNodes, 4, bytes_of(c.view_nodes), 4 * v},
      {SectionId::kReference, 12, bytes_of(c.reference), 12 * v},
      {SectionId::kTriangles, 12, bytes_of(c.triangles), 4 * c.triangles.size()},
      {SectionId::kDisplacements, 12, {}, 12 * v * n, &c.displacements, 3 * v},
      {SectionId::kDisplacementSlopes,
       36,
       {},
       4 * slope_floats * n,
       &c.displacement_slopes,
       slope_floats},
      {SectionId::kClearance, 32, bytes_of(c.clearance), 8 * c.clearance.size()},
      {SectionId::kOnset, sizeof(OnsetCorner), bytes_of(c.onset),
       sizeof(OnsetCorner) * c.onset.size()},
      {SectionId::kMidpointForce, 24 * kMidpointDirections, bytes_of(c.midpoint_force),
       8 * c.midpoint_force.size()},
      {SectionId::kMidpointStiffness, 72 * kMidpointDirections, bytes_of(c.midpoint_stiffness),
       8 * c.midpoint_stiffness.size()},
      {SectionId::kMidpointDisplacementMask, 4, bytes_of(c.midpoint_displacement_mask),
       4 * c.midpoint_displacement_mask.size()},
      {SectionId::kMidpointDisplacements,
       static_cast<std::uint32_t>(48 * kMidpointDirections),
       {},
       4 * midpoint_floats * n,
       &c.midpoint_displacements,
       midpoint_floats},
      {SectionId::kRefinedCells, 4 * kRefinedCellInts, bytes_of(c.refined_cells),
       4 * c.refined_cells.size()},
      {SectionId::kRefinedPoints, 96 * kRefinedPoints, bytes_of(c.refined_points),
       8 * c.refined_points.size()},
      {SectionId::kEighthPoints, 96 * kEighthPoints, bytes_of(c.eighth_points),
       8 * c.eighth_points.size()},
      {SectionId::kCertificate, sizeof(CertificateRecord), {}, 0},  // write_certificate()
      {SectionId::kOnsetTriangles, 72, bytes_of(c.onset_triangles), 8 * c.onset_triangles.size()},
      {SectionId::kOnsetCells, 4, bytes_of(c.onset_cells), 4 * c.onset_cells.size()},
      {SectionId::kOnsetTriangleList, 4, bytes_of(c.onset_triangle_list),
       4 * c.onset_triangle_list.size()},
      {SectionId::kSixteenthPoints, 96 * kSixteenthPoints, bytes_of(c.sixteenth_points),
       8 * c.sixteenth_points.size()},
  };

  const std::filesystem::path tmp = temporary_beside(file);
  OutFile out(tmp);
  try {
    SectionEntry table[kSectionCount];
    const std::uint64_t table_offset = align_up(sizeof(FileHeader));
    const std::uint64_t end =
        write_sections(out, pending, n, align_up(table_offset + sizeof(table)), table);
    write_header_and_table(out, table, table_offset, end);
    out.finish(end);
    replace_file(tmp, file);
  } catch (...) {
    std::error_code ignored;
    std::filesystem::remove(tmp, ignored);
    throw;
  }
}

void write_certificate(const std::filesystem::path& file, const CertificateRecord& record) {
  PlaybackFile(file).verify();  // a damaged file is refused, not sealed with fresh checksums
  const int in = ::open(file.c_str(), O_RDONLY | O_CLOEXEC);
  if (in < 0) throw EnvironmentError(file.string() + ": cannot open: " + os_error_text(errno));
  struct Closer {
    int fd;
    ~Closer() { ::close(fd); }
  } closer{in};
  auto read_at = [&](std::uint64_t offset, void* data, std::size_t bytes) {
    char* p = static_cast<char*>(data);
    while (bytes > 0) {
      const ssize_t n = ::pread(in, p, bytes, static_cast<off_t>(offset));
      if (n < 0 && errno == EINTR) continue;
      if (n < 0) throw EnvironmentError(file.string() + ": cannot read: " + os_error_text(errno));
      if (n == 0) throw InputError(file.string() + ": truncated playback file");
      p += n;
      offset += static_cast<std::uint64_t>(n);
      bytes -= static_cast<std::size_t>(n);
    }
  };
  FileHeader header{};
  read_at(0, &header, sizeof(header));
  if (std::memcmp(header.magic, kMagic, sizeof(kMagic)) != 0 || header.version != kVersion ||
      header.section_count != kSectionCount || header.section_entry_bytes != sizeof(SectionEntry))
    throw InputError(file.string() + ": not a playback file of version " +
                     std::to_string(kVersion) + " (run hapstate-index again)");
  SectionEntry table[kSectionCount];
  read_at(header.section_table_offset, table, sizeof(table));
  SectionEntry* entry = nullptr;
  for (SectionEntry& e : table)
    if (e.id == static_cast<std::uint32_t>(SectionId::kCertificate)) entry = &e;
  if (!entry) throw InputError(file.string() + ": no certificate section in the section table");

  const std::filesystem::path tmp = temporary_beside(file);
  try {
    OutFile out(tmp);
    std::vector<char> buffer(1 << 20);
    for (std::uint64_t at = 0; at < header.file_size;) {
      const std::size_t n =
          static_cast<std::size_t>(std::min<std::uint64_t>(buffer.size(), header.file_size - at));
      read_at(at, buffer.data(), n);
      out.write_at(at, buffer.data(), n);
      at += n;
    }
    // In place of an earlier certificate, else after the last section.
    const std::uint64_t offset =
        entry->bytes == sizeof(record) ? entry->offset : align_up(header.file_size);
    const std::uint64_t size = std::max<std::uint64_t>(header.file_size, offset + sizeof(record));
    out.write_at(offset, &record, sizeof(record));
    *entry = {static_cast<std::uint32_t>(SectionId::kCertificate), sizeof(record), offset,
              sizeof(record), content_hash(std::as_bytes(std::span(&record, 1))).value};
    seal_header(&header, table, size);
    out.write_at(header.section_table_offset, table, sizeof(table));
    out.write_at(0, &header, sizeof(header));
    out.finish(size);
    std::filesystem::permissions(tmp, std::filesystem::status(file).permissions());
    replace_file(tmp, file);
  } catch (...) {
    std::error_code ignored;
    std::filesystem::remove(tmp, ignored);
    throw;
  }
}

}  // namespace hapstate::playback
