!> What the result writers (VTK, HDF5) receive: this rank's piece of the mesh and fields.
!>
!> Every rank hands the writers its own piece, numbered locally (1-based). Nodes on a piece
!> boundary appear in several pieces; exactly one rank owns each node (node_owned), and
!> global_node/global_cell give each row's 1-based position in the global, rank-independent
!> order (the order of ids in the deck, sorted), so that files written on any number of
!> ranks hold the same data in the same order.
module mefem_output_mesh
  use mefem_kinds, only: wp
  implicit none
  private

  !> Cell topologies, shared by the model and the writers (VTK codes are in vtk_cell_type).
  integer, parameter, public :: TOPO_TRI3 = 1, TOPO_QUAD4 = 2, TOPO_TET4 = 3, &
                                TOPO_PENTA6 = 4, TOPO_HEX8 = 5
  integer, parameter, public :: NODES_OF_TOPO(5) = [3, 4, 4, 6, 8]  !< corner nodes per topology
  !> VTK cell type per topology: triangle 5, quad 9, tetra 10, wedge 13, hexahedron 12
  integer, parameter :: VTK_CELL_OF_TOPO(5) = [5, 9, 10, 13, 12]
  !> XDMF 3 mixed-topology code per topology: triangle 4, quadrilateral 5, tetrahedron 6,
  !> wedge 8, hexahedron 9
  integer, parameter :: XDMF_CELL_OF_TOPO(5) = [4, 5, 6, 8, 9]

  public :: vtk_cell_type, xdmf_cell_type

  !> One rank's piece of the mesh for output.
  type, public :: output_mesh_t
    integer :: nnode = 0                    !< nodes in this piece
    integer :: ncell = 0                    !< cells in this piece
    integer :: nnode_global = 0             !< nodes in the whole mesh
    integer :: ncell_global = 0             !< cells in the whole mesh
    real(wp), allocatable :: x(:,:)         !< (3,nnode) reference coordinates
    integer, allocatable :: node_id(:)      !< (nnode) user node ids
    integer, allocatable :: global_node(:)  !< (nnode) 1-based global position
    logical, allocatable :: node_owned(:)   !< (nnode) true where this rank owns the node
    integer, allocatable :: topology(:)     !< (ncell) TOPO_* code
    integer, allocatable :: cell_start(:)   !< (ncell+1) cell c's nodes: conn(cell_start(c):cell_start(c+1)-1)
    integer, allocatable :: conn(:)         !< local 1-based node indices of all cells
    integer, allocatable :: cell_id(:)      !< (ncell) user element ids
    integer, allocatable :: cell_part(:)    !< (ncell) user part ids
    integer, allocatable :: global_cell(:)  !< (ncell) 1-based global position
  end type output_mesh_t

  !> A named field on nodes or cells: values(ncomp, n).
  type, public :: output_field_t
    character(len=64) :: name = ''          !< name shown in ParaView / dataset name in HDF5
    integer :: ncomp = 1                    !< components per entity (1 scalar, 3 vector, 6 tensor)
    real(wp), allocatable :: values(:,:)    !< (ncomp, nnode or ncell)
  end type output_field_t

contains

  !> VTK cell type code of a mefem topology (VTK_CELL_OF_TOPO; 0 for none).
  pure integer function vtk_cell_type(topology)
    integer, intent(in) :: topology   !< TOPO_* code
    vtk_cell_type = 0
    if (topology >= 1 .and. topology <= size(VTK_CELL_OF_TOPO)) &
      vtk_cell_type = VTK_CELL_OF_TOPO(topology)
  end function vtk_cell_type

  !> XDMF mixed-topology code of a mefem topology (XDMF_CELL_OF_TOPO; 0 for none).
  pure integer function xdmf_cell_type(topology)
    integer, intent(in) :: topology   !< TOPO_* code
    xdmf_cell_type = 0
    if (topology >= 1 .and. topology <= size(XDMF_CELL_OF_TOPO)) &
      xdmf_cell_type = XDMF_CELL_OF_TOPO(topology)
  end function xdmf_cell_type

end module mefem_output_mesh
