!> The explicit solver's state on one rank (mefem_explicit_dynamics drives it, the cell loop of
!> mefem_explicit_cell_forces fills its forces): local nodes in the layout's numbering (mesh
!> nodes, then enriched nodes) and the cells this rank computes, in flat contiguous arrays;
!> in 3D the cells' data live in blocks of BLOCK_CELLS cells in structure-of-arrays order.
module mefem_explicit_state
  use mefem_kinds, only: wp
  use mefem_cells, only: CELL_MAX_NODES
  use mefem_material_state, only: NHIST, BLOCK_CELLS => BLOCK_POINTS
  use mefem_mortar_contact, only: mortar_contact_t
  use mefem_rigid_bodies, only: rigid_bodies_t
  implicit none
  private

  public :: set_to_zero

  !> Local nodes one rigid wall tests.
  type, public :: node_list_t
    integer, allocatable :: nodes(:)           !< local node numbers
  end type node_list_t

  !> One rank's share of the explicit model: local nodes (layout numbering: mesh nodes, then
  !> enriched nodes) and the cells it computes, in flat contiguous arrays.
  type, public :: explicit_state_t
    integer :: dim = 3                         !< 2 (plane strain) or 3
    integer :: nnode = 0                       !< local nodes
    integer :: ncell = 0                       !< local cells
    ! nodes
    real(wp), allocatable :: x0(:,:)           !< (dim, nnode) reference coordinates
    real(wp), allocatable :: u(:,:)            !< (dim, nnode) displacements u^n
    real(wp), allocatable :: v(:,:)            !< (dim, nnode) velocities v^{n+1/2}
    real(wp), allocatable :: v_old(:,:)        !< (dim, nnode) velocities v^{n-1/2} (only with
                                               !< rigid walls, which read it)
    real(wp), allocatable :: a(:,:)            !< (dim, nnode) accelerations a^n
    real(wp), allocatable :: f_int(:,:)        !< (dim, nnode) internal forces at t^n
    real(wp), allocatable :: f_int_new(:,:)    !< (dim, nnode) internal forces being assembled
    real(wp), allocatable :: f_ext(:,:)        !< (dim, nnode) external forces at t^n
    real(wp), allocatable :: f_ext_new(:,:)    !< (dim, nnode) external forces at t^{n+1}
    real(wp), allocatable :: f_con(:,:)        !< (dim, nnode) contact forces at t^n
    real(wp), allocatable :: f_con_new(:,:)    !< (dim, nnode) contact forces at t^{n+1}
    logical :: with_external = .false.         !< nodal or pressure loads (else f_ext = 0)
    ! mortar contact (replicated surfaces) and this rank's view of its nodes
    type(mortar_contact_t) :: contact
    integer, allocatable :: contact_local(:)   !< (contact nodes) local node, 0 if none
    logical, allocatable :: contact_owned(:)   !< (contact nodes) this rank owns it
    real(wp), allocatable :: contact_buffer(:,:) !< (3, contact nodes) gathered positions
    real(wp), allocatable :: mass(:)           !< (nnode) lumped mass (with added mass)
    real(wp), allocatable :: physical_mass(:)  !< (nnode) lumped mass without mass scaling
    integer, allocatable :: node_global(:)     !< (nnode) global node (mesh, then enriched)
    logical, allocatable :: owned(:)           !< (nnode) this rank owns the node
    logical, allocatable :: active(:)          !< (nnode) has mass: integrated
    logical, allocatable :: fixed(:,:)         !< (dim, nnode) SPC / TC fixed dof
    logical :: spc_in_time = .false.           !< an SPC has a BIRTH or DEATH time
    logical, allocatable :: driven(:,:)        !< (dim, nnode) dof moved by a motion this cycle
                                               !< (set and cleared at the prescribed dofs)
    ! prescribed motions of deformable nodes: entry k moves dof prescribed_dof(k) of local
    ! node prescribed_node(k) as model%motions(prescribed_motion(k)) says
    integer :: nprescribed = 0
    integer, allocatable :: prescribed_node(:), prescribed_dof(:), prescribed_motion(:)
    real(wp), allocatable :: prescribed_v_old(:) !< (nprescribed) their v^{n-1/2}, this cycle
    ! cells
    integer, allocatable :: outer(:)           !< local cells touching a shared node (2D:
                                               !< computed first, the exchange overlaps
                                               !< the inner ones)
    integer, allocatable :: inner(:)           !< the other local cells
    ! blocks of the 3D cell loop: the cells grouped by (material, number of nodes) in
    ! ascending cell order and cut into at most BLOCK_CELLS
    integer :: nblock = 0                      !< blocks (3D; 0 in 2D)
    integer, allocatable :: block_start(:)     !< (nblock+1) offsets into block_cell
    integer, allocatable :: block_nodes(:)     !< (nblock) nodes its cells are computed with
                                               !< (block_node_count)
    integer, allocatable :: block_cell(:)      !< local cells, block by block
    ! 3D: the cells' gradients, metric, volume and history live in the blocks, in the block
    ! kernels' structure-of-arrays layout (entry i of block b is cell block_cell(block_start(b)
    ! + i - 1)); grad, w0 and hist above are then not allocated
    integer, allocatable :: cell_block(:)      !< (ncell) block of each local cell
    integer, allocatable :: cell_slot(:)       !< (ncell) its entry in the block
    real(wp), allocatable :: block_grad(:,:,:,:)  !< (BLOCK_CELLS, 3, CELL_MAX_NODES, nblock)
    real(wp), allocatable :: block_w0(:,:,:)   !< (BLOCK_CELLS, 9, nblock) W0 by column
    real(wp), allocatable :: block_weight(:,:) !< (BLOCK_CELLS, nblock) reference volumes
    real(wp), allocatable :: block_hist(:,:,:) !< (BLOCK_CELLS, NHIST, nblock) histories
    integer, allocatable :: cell_global(:)     !< (ncell) global cell index
    integer, allocatable :: cell_element(:)    !< (ncell) first model element of the cell
    integer, allocatable :: nnodes(:)          !< (ncell) nodes of the cell
    integer, allocatable :: nodes(:,:)         !< (CELL_MAX_NODES, ncell) local nodes
    real(wp), allocatable :: grad(:,:,:)       !< (dim, CELL_MAX_NODES, ncell) gradients
    real(wp), allocatable :: weight(:)         !< (ncell) reference area/volume
    integer, allocatable :: material(:)        !< (ncell) material index
    real(wp), allocatable :: lame(:,:)         !< (2, ncell) lambda, mu of the material
    real(wp), allocatable :: w0(:,:,:)         !< (dim, dim, ncell) sum g g^T / m_share
    real(wp), allocatable :: share(:,:)        !< (CELL_MAX_NODES, ncell) mass shares (only
                                               !< with mass scaling, which reads them)
    real(wp), allocatable :: hist(:,:)         !< (NHIST, ncell) material history
    real(wp), allocatable :: cell_force(:,:,:) !< (dim, CELL_MAX_NODES, ncell) contributions
                                               !< (3D: only those to nodes not pushed)
    integer, allocatable :: push_node(:,:)     !< (CELL_MAX_NODES, ncell) 3D: the local node
                                               !< a contribution is added to straight away
                                               !< (pushed assembly), 0: kept in cell_force
    real(wp), allocatable :: added(:,:,:)      !< (1, CELL_MAX_NODES, ncell) added masses
    logical :: mass_scaling = .false.          !< DT2MS < 0 given
    ! time step of the last force evaluation
    real(wp) :: dt_stable = huge(1.0_wp)       !< TSSFAC min 2/omega over local cells
    integer :: dt_cell = 0                     !< local cell that set it
    logical :: failed = .false.                !< a cell failed (message in failure)
    character(len=256) :: failure = ''
    ! rigid bodies (replicated on every rank) and this rank's nodes of them
    type(rigid_bodies_t) :: bodies
    integer :: nrigid = 0                      !< local nodes of rigid bodies
    integer, allocatable :: rigid_node(:)      !< (nrigid) local node
    integer, allocatable :: rigid_body(:)      !< (nrigid) its body
    real(wp), allocatable :: body_force(:,:)   !< (3, bodies) resultant force at t^n
    real(wp), allocatable :: body_moment(:,:)  !< (3, bodies) resultant moment at t^n
    ! rigid walls
    integer :: nwall = 0
    type(node_list_t), allocatable :: wall_nodes(:)  !< (nwall) nodes each wall tests
    real(wp), allocatable :: wall_force(:,:)   !< (3, nwall) force of the owned nodes, last cycle
    real(wp), allocatable :: u_old(:,:)        !< (dim, nnode) u^n while walls need it
    real(wp), allocatable :: v_trial(:,:)      !< (dim, nnode) v^{n+1/2} before the walls
    real(wp) :: wall_work = 0.0_wp             !< work of the walls on the owned nodes
    ! energies accumulated over owned nodes (summed over ranks when written)
    real(wp) :: internal_energy = 0.0_wp
    real(wp) :: contact_energy = 0.0_wp        !< minus the work of the contact forces
    real(wp) :: external_work = 0.0_wp
  end type explicit_state_t

contains

  !> Zero a nodal array as one flat array (an array assignment on the (dim, nnode) component
  !> became one memset call per node).
  pure subroutine set_to_zero(n, a)
    integer, intent(in) :: n                          !< number of entries
    real(wp), intent(out) :: a(n)                     !< the array
    integer :: k
    do k = 1, n
      a(k) = 0.0_wp
    end do
  end subroutine set_to_zero

end module mefem_explicit_state
