// stvd's core library, stvd::stvd: the supported API in one include.
//
// Everything this header includes is the library's supported API: the
// vocabulary (types, errors), metrics, the propagations (Dijkstra and
// Short-Term Vector Dijkstra, Lanthier's Steiner points), the three domains
// with what each can do, the files and memory every entry point checks, and
// what the front ends share. To extend the library with a domain or a norm
// of one's own, add propagation/domain_hooks.hpp, candidate_path.hpp,
// chain_unfolding.hpp and propagation_definition.hpp (docs/architecture.md).
// Every other header (each folder's detail/, the domains' candidate paths and
// the tetrahedral region) is detail: it may change without notice.
#pragma once

// Vocabulary.
#include "stvd/errors.hpp"
#include "stvd/types.hpp"

// Metrics: norms and a norm per vertex.
#include "stvd/metric/metric_field.hpp"
#include "stvd/metric/norms.hpp"

// Propagation: options, results, propagate(); a vertex's predecessor chain;
// many source sets on threads; Lanthier's method.
#include "stvd/lanthier/lanthier_propagation.hpp"
#include "stvd/propagation/predecessor_path.hpp"
#include "stvd/propagation/propagation.hpp"
#include "stvd/propagation/source_set_propagation.hpp"

// Voxel grids: geometry, stencils, the domain and its propagations; geodesic
// paths traced and refined; label regions and their connectivity.
#include "stvd/voxel_grid/grid_geometry.hpp"
#include "stvd/voxel_grid/label_regions.hpp"
#include "stvd/voxel_grid/path_refinement.hpp"
#include "stvd/voxel_grid/path_tracing.hpp"
#include "stvd/voxel_grid/region_connectivity.hpp"
#include "stvd/voxel_grid/stencil.hpp"
#include "stvd/voxel_grid/voxel_grid_domain.hpp"
#include "stvd/voxel_grid/voxel_grid_lanthier.hpp"
#include "stvd/voxel_grid/voxel_grid_propagation.hpp"

// Cell meshes (tetrahedra, polyhedra, edge graphs) and their propagations.
#include "stvd/cell_mesh/cell_mesh_domain.hpp"
#include "stvd/cell_mesh/cell_mesh_lanthier.hpp"
#include "stvd/cell_mesh/cell_mesh_propagation.hpp"
#include "stvd/cell_mesh/tetrahedral_cells.hpp"

// Polygon surfaces, their metrics and propagations.
#include "stvd/surface/surface_domain.hpp"
#include "stvd/surface/surface_lanthier.hpp"
#include "stvd/surface/surface_metrics.hpp"
#include "stvd/surface/surface_propagation.hpp"

// System: the files of a run (inputs read as regular files only, outputs
// that are streams written to), the memory available, threads.
#include "stvd/system/files/file_contents.hpp"
#include "stvd/system/files/file_identity.hpp"
#include "stvd/system/files/output_destination.hpp"
#include "stvd/system/files/output_transaction.hpp"
#include "stvd/system/files/regular_file.hpp"
#include "stvd/system/files/termination_signals.hpp"
#include "stvd/system/interrupter.hpp"
#include "stvd/system/memory.hpp"
#include "stvd/system/parallel_tasks.hpp"

// What the front ends share: every option declared once with its default,
// range and help; a propagation as a user chooses it; what a run will
// allocate; numbers in messages.
#include "stvd/front_end/memory_estimates.hpp"
#include "stvd/front_end/mesh_options.hpp"
#include "stvd/front_end/number_text.hpp"
#include "stvd/front_end/option_declarations.hpp"
#include "stvd/front_end/path_tracing_options.hpp"
#include "stvd/front_end/propagation_choice.hpp"
#include "stvd/front_end/propagation_choice_options.hpp"
#include "stvd/front_end/region_connectivity_options.hpp"
