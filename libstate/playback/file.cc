// PlaybackFile: mapping, O(1) validation at open, and verify().
#include "playback/file_impl.h"

#include "playback/code_id.h"
#include "util/error.h"
#include "util/hash.h"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <string>

namespace hapstate {
namespace {

using playback::SectionEntry;
using playback::SectionId;

std::string section_name(SectionId id) {
  switch (id) {
    case SectionId::kMeta:
      return "meta";
    case SectionId::kCheckpoints:
      return "checkpoints";
    case SectionId::kConfigCheckpoint:
      return "configuration check-points";
    case SectionId::kConfigLevel:
      return "configuration levels";
    case SectionId::kForce:
      return "forces";
    case SectionId::kStiffness:
      return "stiffness";
    case SectionId::kTransitions:
      return "transitions";
    case SectionId::kViewNodes:
      return "view nodes";
    case SectionId::kReference:
      return "reference positions";
    case SectionId::kTriangles:
      return "triangles";
    case SectionId::kDisplacements:
      return "displacements";
    case SectionId::kConfigZero:
      return "zero configurations";
    case SectionId::kDisplacementSlopes:
      return "displacement slopes";
    case SectionId::kClearance:
      return "clearance";
    case SectionId::kOnset:
      return "onset corners";
    case SectionId::kMidpointForce:
      return "midpoint force";
    case SectionId::kMidpointStiffness:
      return "midpoint stiffness";
    case SectionId::kMidpointDisplacementMask:
      return "midpoint displacement mask";
    case SectionId::kMidpointDisplacements:
      return "midpoint displacements";
    case SectionId::kRefinedCells:
      return "refined cells";
    case SectionId::kRefinedPoints:
      return "refined points";
    case SectionId::kCertificate:
      return "certificate";
    case SectionId::kEighthPoints:
      return "eighth-spacing points";
    case SectionId::kSixteenthPoints:
      return "sixteenth-spacing points";
    case SectionId::kOnsetTriangles:
      return "onset triangles";
    case SectionId::kOnsetCells:
      return "onset cells";
    case SectionId::kOnsetTriangleList:
      return "onset triangle list";
  }
  return "section " + std::to_string(static_cast<std::uint32_t>(id));
}

bool finite(const double* v, int n) {
  for (int k = 0; k < n; ++k)
    if (!std::isfinite(v[k])) return false;
  return true;
}

// A check at open found the file unusable: `what` completes "not a usable playback file: ".
struct Unusable {
  std::string what;
};
[[noreturn]] void unusable(const std::string& what) { throw Unusable{what}; }

// The sections the table lists, by id (nullptr / 0 bytes: absent).
struct Sections {
  const std::byte* data[playback::kSectionCount + 1] = {};
  std::uint64_t bytes[playback::kSectionCount + 1] = {};
  std::uint64_t meta_checksum = 0;
  const std::byte* at(SectionId id) const { return data[static_cast<int>(id)]; }
  std::uint64_t size(SectionId id) const { return bytes[static_cast<int>(id)]; }
};

// Sections 24-26: their sizes (the cursor checks the lists it reads; verify() all of them).
void check_onset_sizes(const playback::Meta& m, const Sections& sections) {
  const std::uint64_t triangle_bytes = sections.size(SectionId::kOnsetTriangles);
  const std::uint64_t cells_bytes = sections.size(SectionId::kOnsetCells);
  const std::uint64_t list_bytes = sections.size(SectionId::kOnsetTriangleList);
  if (triangle_bytes % 8 != 0 || cells_bytes % 4 != 0 || list_bytes % 4 != 0)
    unusable("onset triangle sections: sizes not whole");
  const std::int64_t points = std::int64_t(m.dims[0]) * m.dims[1] * m.dims[2];
  if (const char* problem = playback::onset_sizes_problem(triangle_bytes / 8, cells_bytes / 4,
                                                          list_bytes / 4, points, m.contact_radius))
    unusable(problem);
}

// The header at `base` (`size` bytes mapped): magic, version, checksum, size and layout.
void check_header(const std::byte* base, std::size_t size) {
  const playback::FileHeader& h = *reinterpret_cast<const playback::FileHeader*>(base);
  if (std::memcmp(h.magic, playback::kMagic, sizeof(playback::kMagic)) != 0)
    unusable("bad magic at byte 0 (expected HAPSPLAY)");
  if (h.version != playback::kVersion)
    unusable("format version " + std::to_string(h.version) + ", this build reads version " +
             std::to_string(playback::kVersion) + " (run hapstate-index again)");
  const auto header_bytes =
      std::as_bytes(std::span(&h, 1)).first(offsetof(playback::FileHeader, header_checksum));
  if (content_hash(header_bytes).value != h.header_checksum) unusable("header checksum mismatch");
  if (h.file_size != size)
    unusable("truncated or extended: the header says " + std::to_string(h.file_size) +
             " bytes, the file has " + std::to_string(size));
  if (h.header_bytes != sizeof(playback::FileHeader) ||
      h.section_entry_bytes != sizeof(SectionEntry) || h.section_count != playback::kSectionCount)
    unusable("unexpected header or section table layout");
}

// The section table (checked: inside the file, its checksum, each entry's id, alignment and
// extent).
Sections read_sections(const std::byte* base, std::size_t size, const SectionEntry** table) {
  const playback::FileHeader& h = *reinterpret_cast<const playback::FileHeader*>(base);
  const std::uint64_t table_bytes = std::uint64_t{h.section_count} * sizeof(SectionEntry);
  if (h.section_table_offset % 8 != 0 || h.section_table_offset > size ||
      table_bytes > size - h.section_table_offset)
    unusable("section table outside the file");
  *table = reinterpret_cast<const SectionEntry*>(base + h.section_table_offset);
  if (content_hash(std::span(base + h.section_table_offset, table_bytes)).value !=
      h.section_table_checksum)
    unusable("section table checksum mismatch");
  Sections out;
  for (std::uint32_t s = 0; s < h.section_count; ++s) {
    const SectionEntry& e = (*table)[s];
    if (e.id < 1 || e.id > playback::kSectionCount || out.data[e.id])
      unusable("section table entry " + std::to_string(s) + " has a bad or repeated id " +
               std::to_string(e.id));
    const std::string name = section_name(static_cast<SectionId>(e.id));
    if (e.offset % playback::kAlignment != 0)
      unusable("section '" + name + "' is not 64-byte aligned");
    if (e.offset > size || e.bytes > size - e.offset)
      unusable("section '" + name + "' (offset " + std::to_string(e.offset) + ", " +
               std::to_string(e.bytes) + " bytes) runs past the end of the file");
    out.data[e.id] = base + e.offset;
    out.bytes[e.id] = e.bytes;
    if (e.id == static_cast<std::uint32_t>(SectionId::kMeta)) out.meta_checksum = e.checksum;
  }
  return out;
}

// The meta section: its size, checksum, grid, flags, counts and limits.
const playback::Meta& check_meta(const Sections& sections) {
  if (sections.size(SectionId::kMeta) != sizeof(playback::Meta)) unusable("meta section size");
  if (content_hash(std::span(sections.at(SectionId::kMeta), sizeof(playback::Meta))).value !=
      sections.meta_checksum)
    unusable("meta section checksum mismatch");
  const playback::Meta& m2 =
      *reinterpret_cast<const playback::Meta*>(sections.at(SectionId::kMeta));
  for (int a = 0; a < 3; ++a)
    if (m2.dims[a] < 1 || m2.dims[a] > (1 << 20) || !(m2.spacing[a] > 0) ||
        !std::isfinite(m2.origin[a]))
      unusable("meta: bad grid (dims, spacing or origin) on axis " + std::to_string(a));
  if (m2.has_displacement_slopes != 0 && m2.has_displacement_slopes != 1)
    unusable("meta: has_displacement_slopes is " + std::to_string(m2.has_displacement_slopes) +
             ", not 0 or 1");
  if (m2.num_configurations < 1 || m2.num_view_nodes < 0 || m2.num_triangles < 0 ||
      m2.rest_configuration < 0 || m2.rest_configuration >= m2.num_configurations)
    unusable("meta: bad counts");
  return m2;
}

// Whether the file is for a contact (sphere) probe: PlaybackFile::is_contact, before it is open.
bool contact_probe(const playback::Meta& m) {
  return m.probe_mode == static_cast<std::int32_t>(playback::ProbeModeCode::kContact);
}

// Every section's size against what the meta section implies (the optional ones: 0 or that).
void check_section_sizes(const playback::Meta& m2, const Sections& sections) {
  const std::uint64_t n = static_cast<std::uint64_t>(m2.num_configurations);
  const std::uint64_t v = static_cast<std::uint64_t>(m2.num_view_nodes);
  const std::uint64_t points = std::uint64_t(m2.dims[0]) * m2.dims[1] * m2.dims[2];
  const bool contact = contact_probe(m2);
  const std::uint64_t* bytes = sections.bytes;
  const std::pair<SectionId, std::uint64_t> expected[] = {
      {SectionId::kCheckpoints, 8 * points},
      {SectionId::kConfigCheckpoint, 4 * n},
      {SectionId::kConfigLevel, 4 * n},
      {SectionId::kConfigZero, 4 * n},
      {SectionId::kForce, 24 * n},
      {SectionId::kStiffness, 72 * n},
      {SectionId::kTransitions, 104 * n},
      {SectionId::kViewNodes, 4 * v},
      {SectionId::kReference, 12 * v},
      {SectionId::kTriangles, 12 * std::uint64_t(m2.num_triangles)},
      {SectionId::kDisplacements, 12 * v * n},
      {SectionId::kDisplacementSlopes, m2.has_displacement_slopes ? 36 * v * n : 0},
      {SectionId::kClearance, contact ? 32 * points : 0},
      {SectionId::kOnset, contact ? sizeof(playback::OnsetCorner) * n : 0}};
  const std::uint64_t midpoint_bytes = bytes[static_cast<int>(SectionId::kMidpointForce)];
  if (midpoint_bytes != 0 && midpoint_bytes != 24 * playback::kMidpointDirections * n)
    unusable("section 'midpoint force' has " + std::to_string(midpoint_bytes) +
             " bytes, the header implies 0 or " +
             std::to_string(24 * playback::kMidpointDirections * n));
  const std::uint64_t midpoint_k_bytes = bytes[static_cast<int>(SectionId::kMidpointStiffness)];
  if (midpoint_k_bytes != 0 &&
      (midpoint_bytes == 0 || midpoint_k_bytes != 72 * playback::kMidpointDirections * n))
    unusable("section 'midpoint stiffness' has " + std::to_string(midpoint_k_bytes) +
             " bytes, the header implies 0 or " +
             std::to_string(midpoint_bytes == 0 ? 0 : 72 * playback::kMidpointDirections * n));
  const std::uint64_t mask_bytes = bytes[static_cast<int>(SectionId::kMidpointDisplacementMask)];
  const std::uint64_t midpoint_u_bytes = bytes[static_cast<int>(SectionId::kMidpointDisplacements)];
  if (mask_bytes != 0 && mask_bytes != 4 * n)
    unusable("section 'midpoint displacement mask' has " + std::to_string(mask_bytes) +
             " bytes, the header implies 0 or " + std::to_string(4 * n));
  if (midpoint_u_bytes != (mask_bytes == 0 ? 0 : 48 * playback::kMidpointDirections * v * n))
    unusable("section 'midpoint displacements' has " + std::to_string(midpoint_u_bytes) +
             " bytes, the header implies " +
             std::to_string(mask_bytes == 0 ? 0 : 48 * playback::kMidpointDirections * v * n));
  const std::uint64_t refined_cell_bytes = bytes[static_cast<int>(SectionId::kRefinedCells)];
  const std::uint64_t refined_bytes = bytes[static_cast<int>(SectionId::kRefinedPoints)];
  const std::uint64_t cell_bytes = 96 * playback::kRefinedPoints;
  const std::uint64_t cell_ints = 4 * playback::kRefinedCellInts;
  if (refined_cell_bytes != 0 && (refined_cell_bytes != cell_ints * n || midpoint_k_bytes == 0))
    unusable("section 'refined cells' has " + std::to_string(refined_cell_bytes) +
             " bytes, the header implies 0 or " +
             std::to_string(midpoint_k_bytes == 0 ? 0 : cell_ints * n));
  if (refined_bytes % cell_bytes != 0 || (refined_bytes != 0 && refined_cell_bytes == 0))
    unusable("section 'refined points' has " + std::to_string(refined_bytes) +
             " bytes, not a multiple of " + std::to_string(cell_bytes) +
             (refined_cell_bytes == 0 ? " with section 'refined cells'" : ""));
  const std::uint64_t eighth_bytes = bytes[static_cast<int>(SectionId::kEighthPoints)];
  const std::uint64_t eighth_cell_bytes = 96 * playback::kEighthPoints;
  if (eighth_bytes % eighth_cell_bytes != 0 || (eighth_bytes != 0 && refined_bytes == 0))
    unusable("section 'eighth-spacing points' has " + std::to_string(eighth_bytes) +
             " bytes, not a multiple of " + std::to_string(eighth_cell_bytes) +
             (refined_bytes == 0 ? " with section 'refined points'" : ""));
  const std::uint64_t sixteenth_bytes = bytes[static_cast<int>(SectionId::kSixteenthPoints)];
  const std::uint64_t sixteenth_cell_bytes = 96 * playback::kSixteenthPoints;
  if (sixteenth_bytes % sixteenth_cell_bytes != 0 || (sixteenth_bytes != 0 && eighth_bytes == 0))
    unusable("section 'sixteenth-spacing points' has " + std::to_string(sixteenth_bytes) +
             " bytes, not a multiple of " + std::to_string(sixteenth_cell_bytes) +
             (eighth_bytes == 0 ? " with section 'eighth-spacing points'" : ""));
  const std::uint64_t certificate_bytes = bytes[static_cast<int>(SectionId::kCertificate)];
  if (certificate_bytes != 0 && certificate_bytes != sizeof(playback::CertificateRecord))
    unusable("section 'certificate' has " + std::to_string(certificate_bytes) +
             " bytes, the header implies 0 or " +
             std::to_string(sizeof(playback::CertificateRecord)));
  if (!(m2.stiffness_limit >= 0) || !std::isfinite(m2.stiffness_limit))
    unusable("meta: stiffness limit is not a finite number >= 0");
  for (int k = 0; k < 3; ++k)
    if (!(m2.bubble_limit[k] >= 0) || !std::isfinite(m2.bubble_limit[k]))
      unusable("meta: bubble limit " + std::to_string(k) + " is not a finite number >= 0");
  for (const auto& [id, size] : expected)
    if (bytes[static_cast<int>(id)] != size)
      unusable("section '" + section_name(id) + "' has " +
               std::to_string(bytes[static_cast<int>(id)]) + " bytes, the header implies " +
               std::to_string(size));
}

}  // namespace

PlaybackFile::PlaybackFile(const std::filesystem::path& file) : path_(file), impl_(new Impl) {
  auto fail = [&](const std::string& what) -> void {
    if (impl_->base) ::munmap(const_cast<std::byte*>(impl_->base), impl_->size);
    delete impl_;
    impl_ = nullptr;
    throw InputError(path_.string() + ": not a usable playback file: " + what);
  };
  const int fd = ::open(file.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) {
    const int e = errno;
    delete impl_;
    const std::string text = path_.string() + ": cannot open: " + os_error_text(e);
    // No such file is the user's input; permissions, I/O errors and limits are not.
    if (e == ENOENT || e == ENOTDIR || e == EISDIR || e == ELOOP) throw InputError(text);
    throw EnvironmentError(text);
  }
  struct stat st {};
  if (::fstat(fd, &st) != 0 || st.st_size < static_cast<off_t>(sizeof(playback::FileHeader))) {
    ::close(fd);
    fail("shorter than the 64-byte header (" + std::to_string(st.st_size) + " bytes)");
  }
  impl_->size = static_cast<std::size_t>(st.st_size);
  void* m = ::mmap(nullptr, impl_->size, PROT_READ, MAP_SHARED, fd, 0);
  ::close(fd);
  if (m == MAP_FAILED) {
    const int e = errno;
    delete impl_;
    throw EnvironmentError(path_.string() + ": cannot map: " + os_error_text(e));
  }
  Impl& f = *impl_;
  f.base = static_cast<const std::byte*>(m);
  f.header = reinterpret_cast<const playback::FileHeader*>(f.base);
  Sections sections;
  try {
    check_header(f.base, f.size);
    sections = read_sections(f.base, f.size, &f.table);
    f.meta = &check_meta(sections);
    check_section_sizes(*f.meta, sections);
    check_onset_sizes(*f.meta, sections);
  } catch (const Unusable& e) {
    fail(e.what);
  } catch (...) {  // no memory for a message: unmap and pass it on
    ::munmap(const_cast<std::byte*>(impl_->base), impl_->size);
    delete impl_;
    impl_ = nullptr;
    throw;
  }
  const playback::Meta& m2 = *f.meta;
  const bool contact = contact_probe(m2);
  auto section = [&](SectionId id) { return sections.at(id); };
  const std::uint64_t midpoint_bytes = sections.size(SectionId::kMidpointForce);
  const std::uint64_t midpoint_k_bytes = sections.size(SectionId::kMidpointStiffness);
  const std::uint64_t mask_bytes = sections.size(SectionId::kMidpointDisplacementMask);
  const std::uint64_t refined_cell_bytes = sections.size(SectionId::kRefinedCells);
  const std::uint64_t refined_bytes = sections.size(SectionId::kRefinedPoints);
  const std::uint64_t cell_bytes = 96 * playback::kRefinedPoints;
  const std::uint64_t eighth_bytes = sections.size(SectionId::kEighthPoints);
  const std::uint64_t sixteenth_bytes = sections.size(SectionId::kSixteenthPoints);
  const std::uint64_t certificate_bytes = sections.size(SectionId::kCertificate);
  f.checkpoints = reinterpret_cast<const std::int32_t*>(section(SectionId::kCheckpoints));
  f.config_checkpoint =
      reinterpret_cast<const std::int32_t*>(section(SectionId::kConfigCheckpoint));
  f.config_level = reinterpret_cast<const std::int32_t*>(section(SectionId::kConfigLevel));
  f.config_zero = reinterpret_cast<const std::int32_t*>(section(SectionId::kConfigZero));
  f.force = reinterpret_cast<const double*>(section(SectionId::kForce));
  f.stiffness = reinterpret_cast<const double*>(section(SectionId::kStiffness));
  f.transitions = reinterpret_cast<const std::int32_t*>(section(SectionId::kTransitions));
  f.view_nodes = reinterpret_cast<const std::int32_t*>(section(SectionId::kViewNodes));
  f.reference = reinterpret_cast<const float*>(section(SectionId::kReference));
  f.triangles = reinterpret_cast<const std::int32_t*>(section(SectionId::kTriangles));
  f.displacements = reinterpret_cast<const float*>(section(SectionId::kDisplacements));
  if (m2.has_displacement_slopes)
    f.slopes = reinterpret_cast<const float*>(section(SectionId::kDisplacementSlopes));
  if (midpoint_bytes != 0)
    f.midpoint_force = reinterpret_cast<const double*>(section(SectionId::kMidpointForce));
  if (midpoint_k_bytes != 0)
    f.midpoint_stiffness = reinterpret_cast<const double*>(section(SectionId::kMidpointStiffness));
  if (mask_bytes != 0) {
    f.midpoint_mask =
        reinterpret_cast<const std::int32_t*>(section(SectionId::kMidpointDisplacementMask));
    f.midpoint_displacements =
        reinterpret_cast<const float*>(section(SectionId::kMidpointDisplacements));
  }
  if (refined_cell_bytes != 0) {
    f.refined_cells = reinterpret_cast<const std::int32_t*>(section(SectionId::kRefinedCells));
    f.refined_points = reinterpret_cast<const double*>(section(SectionId::kRefinedPoints));
    f.num_refined_cells = static_cast<std::int32_t>(refined_bytes / cell_bytes);
    if (eighth_bytes != 0) {
      f.eighth_points = reinterpret_cast<const double*>(section(SectionId::kEighthPoints));
      f.num_eighth_cells =
          static_cast<std::int32_t>(eighth_bytes / (96 * std::uint64_t(playback::kEighthPoints)));
    }
    if (sixteenth_bytes != 0) {
      f.sixteenth_points = reinterpret_cast<const double*>(section(SectionId::kSixteenthPoints));
      f.num_sixteenth_cells = static_cast<std::int32_t>(
          sixteenth_bytes / (96 * std::uint64_t(playback::kSixteenthPoints)));
    }
  }
  if (certificate_bytes != 0)
    f.certificate =
        reinterpret_cast<const playback::CertificateRecord*>(section(SectionId::kCertificate));
  if (sections.size(SectionId::kOnsetTriangles) != 0 && contact) {
    f.onset_triangles = reinterpret_cast<const double*>(section(SectionId::kOnsetTriangles));
    f.num_onset_triangles =
        static_cast<std::int32_t>(sections.size(SectionId::kOnsetTriangles) / 72);
    f.onset_cells = reinterpret_cast<const std::int32_t*>(section(SectionId::kOnsetCells));
    f.onset_triangle_list =
        reinterpret_cast<const std::int32_t*>(section(SectionId::kOnsetTriangleList));
    f.onset_list_size = static_cast<std::int32_t>(sections.size(SectionId::kOnsetTriangleList) / 4);
  }

  if (contact) {
    f.clearance = reinterpret_cast<const double*>(section(SectionId::kClearance));
    f.onset = reinterpret_cast<const playback::OnsetCorner*>(section(SectionId::kOnset));
  }
}

PlaybackFile::~PlaybackFile() {
  if (impl_ && impl_->base) ::munmap(const_cast<std::byte*>(impl_->base), impl_->size);
  delete impl_;
}

void PlaybackFile::verify() const {
  const Impl& f = *impl_;
  auto fail = [&](const std::string& what) {
    throw InputError(path_.string() + ": verification failed: " + what);
  };
  for (std::uint32_t s = 0; s < f.header->section_count; ++s) {
    const playback::SectionEntry& e = f.table[s];
    if (content_hash(std::span(f.base + e.offset, e.bytes)).value != e.checksum)
      fail("section '" + section_name(static_cast<SectionId>(e.id)) +
           "' checksum mismatch (offset " + std::to_string(e.offset) + ")");
  }
  const playback::Meta& m = *f.meta;
  const std::int64_t n = m.num_configurations;
  const std::int64_t points = std::int64_t(m.dims[0]) * m.dims[1] * m.dims[2];
  if (f.onset_cells)
    if (const char* problem = playback::onset_lists_problem(
            f.onset_triangles, 9 * std::size_t(f.num_onset_triangles), f.onset_cells,
            std::size_t(points) + 1, f.onset_triangle_list, std::size_t(f.onset_list_size), points,
            m.contact_radius))
      fail(problem);
  for (std::int64_t g = 0; g < points; ++g) {
    const std::int32_t first = f.checkpoints[2 * g], count = f.checkpoints[2 * g + 1];
    if (count < 0 || (count > 0 && (first < 0 || first + std::int64_t(count) > n)))
      fail("check-point " + std::to_string(g) + ": configuration range out of bounds");
    for (std::int32_t c = first; count > 0 && c < first + count; ++c)
      if (f.config_checkpoint[c] != g)
        fail("configuration " + std::to_string(c) + ": wrong check-point");
  }
  for (std::int64_t c = 0; c < n; ++c) {
    for (int r = 0; r < 3; ++r)
      if (!std::isfinite(f.force[3 * c + r]))
        fail("configuration " + std::to_string(c) + ": force not finite");
    for (int r = 0; r < 9; ++r)
      if (!std::isfinite(f.stiffness[9 * c + r]))
        fail("configuration " + std::to_string(c) + ": stiffness not finite");
    if (f.onset &&
        (!finite(f.onset[c].force, 3) || !finite(f.onset[c].stiffness, 9) ||
         !finite(f.onset[c].secant, 4) || !finite(f.onset[c].per_depth, 3) ||
         !finite(f.onset[c].per_depth_squared, 3) ||
         !std::isfinite(f.onset[c].displacement_per_depth) || f.onset[c].source < -1 ||
         f.onset[c].source >= n || f.onset[c].depth_source < -1 || f.onset[c].depth_source >= n))
      fail("configuration " + std::to_string(c) + ": onset corner not finite or out of range");
    if (f.config_zero[c] != 0 && f.config_zero[c] != 1)
      fail("configuration " + std::to_string(c) + ": zero flag " +
           std::to_string(f.config_zero[c]) + " is not 0 or 1");
    for (int d = 0; d < grid::kDirections; ++d) {
      const std::int32_t t = f.transitions[grid::kDirections * c + d];
      if (t < playback::kFailed || t >= n)
        fail("configuration " + std::to_string(c) + ", direction " + std::to_string(d) +
             ": transition target " + std::to_string(t) + " out of range");
    }
  }
  for (std::int64_t k = 0; f.midpoint_force && k < 3 * playback::kMidpointDirections * n; ++k)
    if (std::isinf(f.midpoint_force[k]))
      fail("configuration " + std::to_string(k / (3 * playback::kMidpointDirections)) +
           ": midpoint force infinite");
  for (std::int64_t k = 0; f.midpoint_stiffness && k < 9 * playback::kMidpointDirections * n; ++k)
    if (std::isinf(f.midpoint_stiffness[k]))
      fail("configuration " + std::to_string(k / (9 * playback::kMidpointDirections)) +
           ": midpoint stiffness infinite");
  for (std::int64_t c = 0; f.midpoint_mask && c < n; ++c)
    if (f.midpoint_mask[c] < 0 || f.midpoint_mask[c] >= (1 << playback::kMidpointDirections))
      fail("configuration " + std::to_string(c) + ": midpoint displacement mask " +
           std::to_string(f.midpoint_mask[c]) + " out of range");
  for (std::int64_t c = 0; f.refined_cells && c < n; ++c) {
    const std::int32_t* r = f.refined_cells + playback::kRefinedCellInts * c;
    if (r[0] < -1 || r[0] >= f.num_refined_cells || r[1] < 0 || r[1] >= (1 << 18) || r[2] < -1 ||
        r[2] >= f.num_eighth_cells || (r[2] >= 0 && r[0] < 0) || r[3] < 0 || r[3] >= (1 << 18) ||
        r[4] < -1 || r[4] >= f.num_sixteenth_cells || (r[4] >= 0 && r[2] < 0) || r[5] < 0 ||
        r[5] >= (1 << 18))
      fail("configuration " + std::to_string(c) + ": refined cell " + std::to_string(r[0]) +
           ", its eighth-spacing lattice " + std::to_string(r[2]) +
           ", its sixteenth-spacing lattice " + std::to_string(r[4]) + " or their constraints " +
           std::to_string(r[1]) + ", " + std::to_string(r[3]) + ", " + std::to_string(r[5]) +
           " out of range");
  }
  for (std::int64_t k = 0; k < 12 * playback::kRefinedPoints * std::int64_t(f.num_refined_cells);
       ++k)
    if (std::isinf(f.refined_points[k]))
      fail("refined cell " + std::to_string(k / (12 * playback::kRefinedPoints)) +
           ": a force or stiffness is infinite");
  for (std::int64_t k = 0; k < 12 * playback::kEighthPoints * std::int64_t(f.num_eighth_cells); ++k)
    if (std::isinf(f.eighth_points[k]))
      fail("eighth-spacing lattice " + std::to_string(k / (12 * playback::kEighthPoints)) +
           ": a force or stiffness is infinite");
  for (std::int64_t k = 0;
       k < 12 * playback::kSixteenthPoints * std::int64_t(f.num_sixteenth_cells); ++k)
    if (std::isinf(f.sixteenth_points[k]))
      fail("sixteenth-spacing lattice " + std::to_string(k / (12 * playback::kSixteenthPoints)) +
           ": a force or stiffness is infinite");
  for (std::int64_t g = 0; f.clearance && g < points; ++g)
    if (!finite(f.clearance + 4 * g, 4))
      fail("check-point " + std::to_string(g) + ": clearance not finite");
  for (std::int64_t k = 0; k < 3 * std::int64_t(m.num_triangles); ++k)
    if (f.triangles[k] < 0 || f.triangles[k] >= m.num_view_nodes)
      fail("triangle " + std::to_string(k / 3) + ": view node out of range");
  for (std::int64_t k = 0; k < m.num_view_nodes; ++k)
    if (f.view_nodes[k] < 0 || f.view_nodes[k] >= m.num_mesh_nodes)
      fail("view node " + std::to_string(k) + ": mesh node out of range");
}

std::int32_t PlaybackFile::num_configurations() const { return impl_->meta->num_configurations; }
std::int32_t PlaybackFile::num_view_nodes() const { return impl_->meta->num_view_nodes; }
std::int32_t PlaybackFile::num_mesh_nodes() const { return impl_->meta->num_mesh_nodes; }
bool PlaybackFile::view_is_all_nodes() const { return impl_->meta->view_all_nodes != 0; }
bool PlaybackFile::is_contact() const { return contact_probe(*impl_->meta); }
bool PlaybackFile::is_zero_configuration(std::int32_t c) const {
  return impl_->config_zero[c] == 1;
}
std::span<const std::int32_t> PlaybackFile::view_nodes() const {
  return {impl_->view_nodes, static_cast<std::size_t>(impl_->meta->num_view_nodes)};
}
std::span<const float> PlaybackFile::reference_positions() const {
  return {impl_->reference, 3 * static_cast<std::size_t>(impl_->meta->num_view_nodes)};
}
std::span<const std::int32_t> PlaybackFile::triangles() const {
  return {impl_->triangles, 3 * static_cast<std::size_t>(impl_->meta->num_triangles)};
}
static std::array<double, 3> vec3(const double* v) { return {v[0], v[1], v[2]}; }
std::array<double, 3> PlaybackFile::rest_position() const {
  return vec3(impl_->meta->rest_position);
}
std::array<double, 3> PlaybackFile::grid_origin() const { return vec3(impl_->meta->origin); }
std::array<double, 3> PlaybackFile::grid_spacing() const { return vec3(impl_->meta->spacing); }
std::array<std::int32_t, 3> PlaybackFile::grid_lo() const {
  return {impl_->meta->lo[0], impl_->meta->lo[1], impl_->meta->lo[2]};
}
std::array<std::int32_t, 3> PlaybackFile::grid_dims() const {
  return {impl_->meta->dims[0], impl_->meta->dims[1], impl_->meta->dims[2]};
}
double PlaybackFile::max_force() const { return impl_->meta->max_force; }
double PlaybackFile::force_change_bound() const { return impl_->meta->force_change_bound; }
std::array<double, 3> PlaybackFile::force(std::int32_t c) const {
  return vec3(impl_->force + 3 * std::int64_t(c));
}
std::array<double, 9> PlaybackFile::stiffness(std::int32_t c) const {
  std::array<double, 9> k;
  std::memcpy(k.data(), impl_->stiffness + 9 * std::int64_t(c), sizeof(k));
  return k;
}
std::span<const float> PlaybackFile::displacements(std::int32_t c) const {
  const std::size_t v = static_cast<std::size_t>(impl_->meta->num_view_nodes);
  return {impl_->displacements + 3 * v * static_cast<std::size_t>(c), 3 * v};
}

bool PlaybackFile::has_displacement_slopes() const { return impl_->slopes != nullptr; }

std::int32_t PlaybackFile::transition_entry(std::int32_t c, int d) const {
  return impl_->transitions[grid::kDirections * static_cast<std::int64_t>(c) + d];
}
std::uint64_t PlaybackFile::scene_hash() const { return impl_->meta->scene_hash; }
std::uint64_t PlaybackFile::source_hash() const { return impl_->meta->source_hash; }

std::optional<PlaybackCertificate> PlaybackFile::certificate() const {
  const playback::CertificateRecord* r = impl_->certificate;
  if (!r || r->measured_source_hash != impl_->meta->source_hash ||
      r->measured_code_id != playback_code_id())
    return std::nullopt;
  PlaybackCertificate c;
  c.paths = r->paths;
  c.steps_per_path = r->steps_per_path;
  c.steps = r->steps;
  c.failed_steps = r->failed_steps;
  for (int s = 0; s < 2; ++s) {
    c.force_error_worst[s] = r->force_error_worst[s];
    c.force_error_p99[s] = r->force_error_p99[s];
    c.force_error_worst_n[s] = r->force_error_worst_n[s];
    c.deformation_error_worst[s] = r->deformation_error_worst[s];
  }
  c.stiffness_n_per_mm = r->stiffness_n_per_mm;
  c.query_median_ns = r->query_median_ns;
  c.query_p999_ns = r->query_p999_ns;
  return c;
}

std::span<const float> PlaybackFile::displacement_slopes(std::int32_t c, int axis) const {
  if (!impl_->slopes) return {};
  const std::size_t v = static_cast<std::size_t>(impl_->meta->num_view_nodes);
  return {impl_->slopes + 3 * v * (3 * static_cast<std::size_t>(c) + axis), 3 * v};
}

}  // namespace hapstate
