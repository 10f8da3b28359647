!> The explicit solver's state on one rank (mefem_explicit_dynamics drives it, the cell loop of
!> mefem_explicit_cell_forces fills its forces): local nodes in the layout's numbering (mesh
!> nodes, then enriched nodes) and the cells this rank computes, in flat contiguous arrays;
!> in 3D the cells' data live in blocks of BLOCK_CELLS cells in structure-of-arrays order.
module mefem_explicit_state
  use, intrinsic :: iso_c_binding, only: c_ptr, c_f_pointer
  use mefem_kinds, only: wp, i1, i8
  use mefem_cells, only: CELL_MAX_NODES
  use mefem_material_state, only: NHIST, BLOCK_CELLS => BLOCK_POINTS
  use mefem_stable_time_step, only: METRIC_ENTRIES
  use mefem_mortar_contact, only: mortar_contact_t
  use mefem_tied_contact, only: tied_nodes_t
  use mefem_rigid_bodies, only: rigid_bodies_t
  use mefem_comm, only: comm_arena_t, comm_arena_create, comm_arena_array, &
                        comm_arena_peer_array, comm_arena_on_node, comm_min_request_t
  implicit none
  private

  public :: set_to_zero, state_arena_create, state_peer_view

  integer, parameter :: ARENA_SIZES = 5                !< sizes recorded in the arena's array 1
  integer, parameter :: ARENA_ARRAYS = 21              !< arrays in the arena (arena_shapes)
  !> which of them hold reals (the others default integers)
  logical, parameter :: ARENA_REAL(ARENA_ARRAYS) = [.false., .true., .false., .false., .true., &
      .false., .true., .false., .true., .true., .true., .false., .false., .false., .false., &
      .false., .true., .true., .true., .true., .true.]
  integer(i8), parameter :: INT_BYTES = storage_size(0)/8       !< bytes of a default integer
  integer(i8), parameter :: REAL_BYTES = storage_size(1.0_wp)/8 !< bytes of a real(wp)

  !> A list of node numbers (the local nodes a rigid wall tests, the contact nodes of a force
  !> transducer).
  type, public :: node_list_t
    integer, allocatable :: nodes(:)           !< node numbers
  end type node_list_t

  !> One rank's share of the explicit model: local nodes (layout numbering: mesh nodes, then
  !> enriched nodes) and the cells it computes, in flat contiguous arrays.
  !>
  !> The arrays a cell's computation reads or writes (displacements, the cells' nodes, data,
  !> histories and force contributions: the pointer components) live in the rank's segment of
  !> a node-shared arena (state_arena_create), so that another rank of the same node can
  !> compute some of this rank's cell blocks when it has run out of its own (the cell loop's
  !> work stealing, mefem_explicit_cell_forces): it does so through a view of this state
  !> (state_peer_view) whose pointers are this rank's arrays.
  type, public :: explicit_state_t
    integer :: dim = 3                         !< 2 (plane strain) or 3
    integer :: nnode = 0                       !< local nodes
    integer :: ncell = 0                       !< local cells
    ! nodes
    real(wp), allocatable :: x0(:,:)           !< (dim, nnode) reference coordinates
    real(wp), pointer, contiguous :: u(:,:) => null() !< (dim, nnode) displacements u^n
    real(wp), allocatable :: v(:,:)            !< (dim, nnode) velocities v^{n+1/2}
    real(wp), allocatable :: v_old(:,:)        !< (dim, nnode) velocities v^{n-1/2} (only with
                                               !< rigid walls, which read it)
    real(wp), allocatable :: a(:,:)            !< (dim, nnode) accelerations a^n
    real(wp), allocatable :: f_int(:,:)        !< (dim, ntarget) internal forces at t^n (the
                                               !< nodes' columns; swapped with f_int_new)
    real(wp), allocatable :: f_int_new(:,:)    !< (dim, ntarget) internal forces being assembled
                                               !< (nodes, then the layout's partial sums)
    real(wp), allocatable :: f_ext(:,:)        !< (dim, nnode) external forces at t^n
    real(wp), allocatable :: f_ext_new(:,:)    !< (dim, nnode) external forces at t^{n+1}
    real(wp), allocatable :: f_con(:,:)        !< (dim, nnode) contact forces at t^n
    real(wp), allocatable :: f_con_new(:,:)    !< (dim, nnode) contact forces at t^{n+1}
    logical :: with_external = .false.         !< nodal, pressure or body loads (else f_ext = 0)
    ! body loads (*LOAD_BODY_): nodal force -body_mass a(t); rigid bodies -M a(t)
    real(wp), allocatable :: body_mass(:)      !< (nnode) physical lumped mass of the nodes
                                               !< the body loads act on, 0 elsewhere
    real(wp), allocatable :: body_load_mass(:) !< (bodies) the mass body loads act on (its
                                               !< elements' if its part takes them, plus its
                                               !< merged nodes' that take them)
    real(wp), allocatable :: body_load(:,:)    !< (3, bodies) its body load at t^n
    real(wp) :: body_load_work = 0.0_wp        !< work of the rigid bodies' body loads
                                               !< (replicated on every rank)
    ! mortar contact (replicated surfaces) and this rank's view of its nodes
    type(mortar_contact_t) :: contact
    integer, allocatable :: contact_local(:)   !< (contact nodes) local node, 0 if none
    logical, allocatable :: contact_owned(:)   !< (contact nodes) this rank owns it
    real(wp), allocatable :: contact_buffer(:,:) !< (3, contact nodes) gathered positions
    ! tied contacts (replicated tie data, mefem_explicit_ties) and this rank's view of them
    type(tied_nodes_t) :: tied
    integer, allocatable :: tie_slave_local(:)   !< (tied nodes) local node, 0 if none
    integer, allocatable :: tie_master_local(:)  !< (master nodes) local node, 0 if none
    real(wp), allocatable :: tie_buffer(:,:)     !< (4, tied nodes) their force and mass
    real(wp), allocatable :: tie_master_buffer(:,:) !< (3, master nodes) their accelerations
    logical, allocatable :: tied_node(:)         !< (nnode) a tied node (its SPCs overridden)
    logical, allocatable :: tie_fixed(:,:)       !< (3, tied nodes) their own SPCs (back in
                                                 !< force when a tiebreak releases the node)
    ! force transducers: the contact nodes of each (contact-node numbering, ascending)
    type(node_list_t), allocatable :: transducer_nodes(:)
    integer, allocatable :: transducer_id(:)     !< (transducers) its rcforc number
    real(wp), allocatable :: mass(:)           !< (nnode) lumped mass (with added mass)
    real(wp), allocatable :: physical_mass(:)  !< (nnode) lumped mass without mass scaling
    integer, allocatable :: node_global(:)     !< (nnode) global node (mesh, then enriched)
    logical, allocatable :: owned(:)           !< (nnode) this rank owns the node
    logical, allocatable :: active(:)          !< (nnode) has mass: integrated
    logical, allocatable :: bubble(:)          !< (nnode) an enriched node: its dof is the
                                               !< bubble amplitude (no translation, no
                                               !< momentum; its mass is inertia only)
    logical, allocatable :: fixed(:,:)         !< (dim, nnode) SPC / TC fixed dof
    logical :: spc_in_time = .false.           !< an SPC has a BIRTH or DEATH time
    logical, allocatable :: driven(:,:)        !< (dim, nnode) dof moved by a motion this cycle
                                               !< (set and cleared at the prescribed dofs)
    ! prescribed motions of deformable nodes: entry k moves dof prescribed_dof(k) of local
    ! node prescribed_node(k) as model%motions(prescribed_motion(k)) says
    integer :: nprescribed = 0
    integer, allocatable :: prescribed_node(:), prescribed_dof(:), prescribed_motion(:)
    real(wp), allocatable :: prescribed_v_old(:) !< (nprescribed) their v^{n-1/2}, this cycle
    logical, allocatable :: was_driven(:)      !< (nprescribed) the dof was driven in the
                                               !< last cycle (update_velocities)
    ! skew conditions (SPCs in a local system, node motions along a vector VID): entry k
    ! acts on the velocity of local node skew_node(k) along the unit vector skew_dir(:, k):
    ! an SPC (skew_source -index of the SPC) keeps that component zero; a motion (skew_source
    ! the motion's index) sets it, and with DOF -4 (skew_whole) zeroes the rest as well
    integer :: nskew = 0
    integer, allocatable :: skew_node(:), skew_source(:)
    real(wp), allocatable :: skew_dir(:,:)     !< (3, nskew)
    logical, allocatable :: skew_whole(:)      !< (nskew)
    real(wp), allocatable :: skew_v_old(:,:)   !< (dim, nskew) v^{n-1/2} of the node
    ! SPCs in moving systems (*DEFINE_COORDINATE_NODES FLAG 1): their directions follow the
    ! systems' nodes (mefem_explicit_skew update_moving_frames)
    integer, allocatable :: skew_system(:)     !< (nskew) the moving system, or 0
    integer, allocatable :: skew_axis(:)       !< (nskew) its local axis (moving)
    integer, allocatable :: skew_earlier(:)    !< (nskew) the node's entry before, or 0
    integer :: n_moving = 0                    !< moving systems with SPCs (every rank alike)
    integer, allocatable :: moving_system(:)   !< (n_moving) their model indices
    integer, allocatable :: moving_first_axis(:) !< (n_moving) DIR: the axis of N1 N2
    integer, allocatable :: moving_local(:,:)  !< (3, n_moving) N1 N2 N3 as local nodes, or 0
    real(wp), allocatable :: moving_x(:,:)     !< (3, 3 n_moving) their current positions
                                               !< (N1 N2 N3 of system k: 3 k - 2 .. 3 k)
    ! cells
    ! blocks of the 3D cell loop: the cells grouped by (material, number of nodes) in
    ! ascending cell order and cut into at most BLOCK_CELLS
    integer :: nblock = 0                      !< blocks (3D; 0 in 2D)
    integer, pointer, contiguous :: block_start(:) => null() !< (nblock+1) offsets into block_cell
    integer, pointer, contiguous :: block_nodes(:) => null()
                                               !< (nblock) nodes its cells are computed with
                                               !< (block_node_count)
    integer, pointer, contiguous :: block_cell(:) => null() !< local cells, block by block
    ! 3D: the cells' gradients, metric, volume and history live in the blocks, in the block
    ! kernels' structure-of-arrays layout (entry i of block b is cell block_cell(block_start(b)
    ! + i - 1)); grad, w0 and hist above are then not allocated
    integer, pointer, contiguous :: cell_block(:) => null() !< (ncell) block of each local cell
    integer, pointer, contiguous :: cell_slot(:) => null() !< (ncell) its entry in the block
    real(wp), pointer, contiguous :: block_grad(:,:,:,:) => null()
                                               !< (BLOCK_CELLS, 3, CELL_MAX_NODES, nblock)
    real(wp), pointer, contiguous :: block_w0(:,:,:) => null()
                                               !< (BLOCK_CELLS, METRIC_ENTRIES, nblock) W0
                                               !< packed (metric_packed)
    real(wp), pointer, contiguous :: block_weight(:,:) => null()
                                               !< (BLOCK_CELLS, nblock) reference volumes
    real(wp), pointer, contiguous :: block_hist(:,:,:) => null()
                                               !< (BLOCK_CELLS, NHIST, nblock) histories
    real(wp), pointer, contiguous :: block_omega0(:,:) => null()
                                               !< (BLOCK_CELLS, nblock) the step bound's
                                               !< reference factor (cell_reference_bound)
    integer, allocatable :: cell_global(:)     !< (ncell) global cell index
    integer, pointer, contiguous :: cell_element(:) => null()
                                               !< (ncell) first model element of the cell
    integer, pointer, contiguous :: nnodes(:) => null() !< (ncell) nodes of the cell
    integer, pointer, contiguous :: nodes(:,:) => null() !< (CELL_MAX_NODES, ncell) local nodes
    real(wp), allocatable :: grad(:,:,:)       !< (dim, CELL_MAX_NODES, ncell) gradients
    real(wp), pointer, contiguous :: weight(:) => null() !< (ncell) reference area/volume
    integer, pointer, contiguous :: material(:) => null() !< (ncell) material index
    real(wp), pointer, contiguous :: lame(:,:) => null() !< (2, ncell) lambda, mu of the material
    real(wp), allocatable :: w0(:,:,:)         !< (dim, dim, ncell) sum g g^T / m_share
    real(wp), pointer, contiguous :: share(:,:) => null()
                                               !< (CELL_MAX_NODES, ncell) mass shares (only
                                               !< with mass scaling, which reads them)
    real(wp), allocatable :: hist(:,:)         !< (NHIST, ncell) material history
    real(wp), pointer, contiguous :: cell_force(:,:,:) => null()
                                               !< (dim, CELL_MAX_NODES, ncell) contributions
                                               !< (3D: only those to columns not pushed)
    integer, allocatable :: push_node(:,:)     !< (CELL_MAX_NODES, ncell) 3D: the column of
                                               !< f_int_new (node, or partial sum of the
                                               !< node's chunk) a contribution is added to
                                               !< straight away (pushed assembly), 0: kept
                                               !< in cell_force
    real(wp), pointer, contiguous :: added(:,:,:) => null()
                                               !< (1, CELL_MAX_NODES, ncell) added masses
    logical :: mass_scaling = .false.          !< DT2MS < 0 given
    ! nodal-pressure tetrahedra (ELFORM 13; doc/theory.md 2.7): J averaged at the nodes over
    ! the ELFORM 13 elements of one material, Jbar of an element the mean of its nodes'
    logical :: nodal_pressure = .false.        !< the model has ELFORM 13 cells (on any rank:
                                               !< the nodal sums are collective)
    integer, allocatable :: np_cells(:)        !< local ELFORM 13 cells, ascending
    logical, allocatable :: np_cell(:)         !< (ncell) an ELFORM 13 cell
    real(wp), allocatable :: np_volume0(:)     !< (nnode) reference volume of the node: sum of
                                               !< V0/4 of its ELFORM 13 elements (0: none)
    logical, allocatable :: np_mixed(:)        !< (nnode) ELFORM 13 elements of different
                                               !< materials meet: each uses its own J there
    real(wp), allocatable :: np_node_j(:)      !< (nnode) nodal J = V/V0 of this cycle
    real(wp), allocatable :: np_node_p(:)      !< (nnode) nodal Cauchy pressure of this cycle
    real(wp), allocatable :: np_jbar(:)        !< (ncell) Jbar of the cell's last update
    real(wp), allocatable :: np_pressure(:)    !< (ncell) Cauchy pressure of the material at
                                               !< Fbar, tr(tau)/(3 Jbar)
    real(wp), allocatable :: np_force_pressure(:) !< (ncell) the pressure of the forces: the
                                               !< mean of the nodal pressures
    real(wp), allocatable :: np_deviator(:,:)  !< (6, ncell) dev(tau_bar)/J of the last update
                                               !< (Voigt: xx yy zz xy yz zx)
    real(wp), allocatable :: np_area(:,:,:)    !< (3, 4, ncell) V0 adj(F)^T g_a of the last
                                               !< update: the forces per unit pressure
    integer, allocatable :: np_column(:,:)     !< (4, size(np_cells)) the assembly column of
                                               !< each corner (halo source_target)
    real(wp), allocatable :: np_sums(:,:)      !< (1, ntarget) the nodal sums
    ! one-point hexahedra (ELFORM 1; doc/theory.md 2.8): their hourglass data in the blocks'
    ! layout (entry i of block b's data: the block's i-th cell)
    logical :: hourglass = .false.             !< the model has hexahedral cells (any rank)
    integer, allocatable :: block_hex(:)       !< (nblock) the block's index in the arrays
                                               !< below, 0 if it has no hexahedra
    integer(i1), allocatable :: hex_h(:,:,:,:) !< (BLOCK_CELLS, CELL_MAX_NODES, 4, blocks of
                                               !< hexahedra) base vectors h_aI per node
    real(wp), allocatable :: hex_hx(:,:,:,:)   !< (BLOCK_CELLS, 3, 4, blocks) hX_a = sum_I
                                               !< h_aI X_I (gamma = h - hX . B)
    integer(i1), allocatable :: hex_corner(:,:,:)  !< (BLOCK_CELLS, 8, blocks) node slot of
                                               !< each corner (a pentahedron: repeated)
    real(wp), allocatable :: hex_stiffness(:,:,:)  !< (BLOCK_CELLS, 6, blocks) K
    real(wp), allocatable :: hex_viscosity(:,:)    !< (BLOCK_CELLS, blocks) c
    logical, allocatable :: hex_viscous(:)     !< (blocks) some cell has a viscous form
    real(wp), allocatable :: hex_metric(:,:)   !< (BLOCK_CELLS, blocks) bound of lambda_max(G)
    logical, allocatable :: hex_rule(:,:)      !< (BLOCK_CELLS, blocks) LS-DYNA's
                                               !< characteristic length rule may set the
                                               !< cell's step: a node of it lies inside the
                                               !< body (explicit_dynamics)
    real(wp) :: hourglass_stored = 0.0_wp      !< energy of the stiffness forms, this rank's
                                               !< cells at the last force evaluation
    real(wp) :: hourglass_power = 0.0_wp       !< power of the viscous forms, likewise
    real(wp) :: hourglass_dissipated = 0.0_wp  !< work of the viscous forms so far (this rank)
    ! time step of the last force evaluation
    real(wp) :: dt_step = 0.0_wp               !< the step of the positions the forces are
                                               !< computed at (VP = 1: the plastic rate)
    real(wp) :: exact_step_below = huge(1.0_wp) !< a cell whose quick step bound is above
                                               !< this takes it, the others their exact bound
                                               !< (block_forces; huge: every cell exact)
    real(wp) :: dt_stable = huge(1.0_wp)       !< TSSFAC min 2/omega over the cells computed
    integer :: dt_element = 0                  !< model element (first of its cell) that set it
    logical :: failed = .false.                !< a cell failed (message in failure)
    character(len=256) :: failure = ''
    type(comm_min_request_t) :: dt_reduction   !< the next step's minimum over the ranks, in
                                               !< flight from the cell loop to next_time_step
    ! node-shared memory of the pointer components; blocks computed for other ranks
    type(comm_arena_t) :: arena
    type(explicit_state_t), allocatable :: peers(:)  !< 3D: views of the other ranks of this
                                               !< node, whose blocks this rank may compute
    integer, allocatable :: peer_rank(:)       !< (size(peers)) their world ranks
    logical :: new_split = .false.             !< the mass split has just been made
                                               !< (explicit_mass_split): exact step bounds
    logical :: exact_steps = .false.           !< MEFEM_EXACT_STEPS=1 (tests): every cell's
                                               !< exact step bound, no quick ones
    logical :: steal_test = .false.            !< MEFEM_STEAL_TEST=1: rank 0 leaves half of
                                               !< its blocks to the others (tests)
    integer(i8) :: blocks_for_others = 0       !< other ranks' blocks computed here (run)
    integer(i8) :: blocks_by_others = 0        !< this rank's blocks computed by others (run)
    integer(i8) :: exact_bound_blocks = 0      !< blocks computed here whose step bound was
                                               !< the exact one (run; block_forces)
    integer(i8) :: bound_blocks = 0            !< blocks of this rank's cell loops (run)
    ! rigid bodies (replicated on every rank) and this rank's nodes of them
    type(rigid_bodies_t) :: bodies
    integer :: nrigid = 0                      !< local nodes of rigid bodies
    integer, allocatable :: rigid_node(:)      !< (nrigid) local node
    integer, allocatable :: rigid_body(:)      !< (nrigid) its body
    integer, allocatable :: rigid_slot(:)      !< (nrigid) its place among all rigid-body
                                               !< nodes of the model (ascending global node)
    integer, allocatable :: slot_body(:)       !< (all rigid-body nodes) body of each place
    real(wp), allocatable :: rigid_buffer(:,:) !< (6, all rigid-body nodes) position and
                                               !< force of the nodes with a force this cycle
    logical, allocatable :: rigid_present(:)   !< (all rigid-body nodes) filled this cycle
    real(wp), allocatable :: rigid_send(:)     !< (7 nrigid) this rank's records (place,
                                               !< position, force) of owned loaded nodes
    real(wp), allocatable :: rigid_all(:)      !< every rank's records (grows as needed)
    real(wp), allocatable :: body_force(:,:)   !< (3, bodies) resultant force at t^n
    real(wp), allocatable :: body_moment(:,:)  !< (3, bodies) resultant moment at t^n
    ! rigid walls
    integer :: nwall = 0
    type(node_list_t), allocatable :: wall_nodes(:)  !< (nwall) nodes each wall tests
    real(wp), allocatable :: wall_force(:,:)   !< (3, nwall) force of the owned nodes, last cycle
    real(wp), allocatable :: wall_shift(:,:)   !< (3, nwall) displacement of a moving wall
    real(wp), allocatable :: u_old(:,:)        !< (dim, nnode) u^n while walls need it
    real(wp), allocatable :: v_trial(:,:)      !< (dim, nnode) v^{n+1/2} before the walls
    real(wp) :: wall_work = 0.0_wp             !< work of the walls on the owned nodes
    ! erosion (materials with a failure strain): a failed point keeps its history with
    ! HIST_ALPHA negated (the mark of a failed point) and carries no stress
    logical :: erosion = .false.               !< some material of the model fails
    real(wp) :: time = 0.0_wp                  !< the time of the cell loop (FAILTM)
    integer :: n_new_eroded = 0                !< cells this rank found failed this cycle
    integer, allocatable :: new_eroded(:)      !< their global cell indices
    integer, allocatable :: eroded_all(:)      !< every rank's, gathered (erosion_update)
    real(wp) :: eroded_energy = 0.0_wp         !< internal energy of the cells this rank
                                               !< eroded (failed_point_energy x V0), so far
    integer :: eroded_cells = 0                !< cells eroded in the model so far
    integer, allocatable :: live_cells(:)      !< (model elements) cells of each element not
                                               !< eroded (every rank alike)
    integer, allocatable :: cell_elements(:,:) !< (2, global cells) the elements of a cell
                                               !< (0: none), for live_cells
    logical, allocatable :: cell_counted(:)    !< (ncell) a failed cell already counted
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


  !> Create the node-shared arena of the cell loop's arrays (collective over all ranks) and
  !> point the state's pointer components at it: sizes from s%dim, s%nnode, s%ncell,
  !> s%mass_scaling and nblock (3D blocks; 0 in 2D). The arrays are left undefined; the
  !> first one records the sizes for the views of other ranks.
  subroutine state_arena_create(s, nblock)
    type(explicit_state_t), intent(inout) :: s        !< state (sizes set)
    integer, intent(in) :: nblock                     !< 3D blocks (0 in 2D)
    integer(i8) :: shapes(4, ARENA_ARRAYS)
    integer, pointer :: sizes(:)
    integer :: k
    s%nblock = nblock
    shapes = arena_shapes(s)
    call comm_arena_create(s%arena, [(product(shapes(:, k))* &
                                      merge(REAL_BYTES, INT_BYTES, ARENA_REAL(k)), &
                                      k = 1, ARENA_ARRAYS)])
    call c_f_pointer(comm_arena_array(s%arena, 1), sizes, [ARENA_SIZES])
    sizes = [s%dim, s%nnode, s%ncell, nblock, merge(1, 0, s%mass_scaling)]
    call associate_arrays(s, [(comm_arena_array(s%arena, k), k = 1, ARENA_ARRAYS)])
  end subroutine state_arena_create

  !> A view of the state of world rank `rank` (same node; its arena created and its sizes
  !> written, e.g. after a barrier): the pointer components and sizes of `view` are that
  !> rank's, everything else is empty. ok = .false. when the rank is on another node.
  subroutine state_peer_view(s, rank, view, ok)
    type(explicit_state_t), intent(in) :: s           !< this rank's state (its arena)
    integer, intent(in) :: rank                       !< the other rank (world, 0-based)
    type(explicit_state_t), intent(out) :: view       !< its view
    logical, intent(out) :: ok                        !< a view was made
    integer, pointer :: sizes(:)
    integer :: k
    ok = comm_arena_on_node(s%arena, rank)
    if (.not. ok) return
    call c_f_pointer(comm_arena_peer_array(s%arena, rank, 1), sizes, [ARENA_SIZES])
    view%dim = sizes(1)
    view%nnode = sizes(2)
    view%ncell = sizes(3)
    view%nblock = sizes(4)
    view%mass_scaling = sizes(5) == 1
    call associate_arrays(view, [(comm_arena_peer_array(s%arena, rank, k), k = 1, ARENA_ARRAYS)])
  end subroutine state_peer_view

  !> Shapes of the arena's arrays (unused trailing extents 1), from the sizes in `s`: array 1
  !> the sizes themselves, then those associate_arrays points at, in its order.
  pure function arena_shapes(s) result(shapes)
    type(explicit_state_t), intent(in) :: s           !< state or view (sizes set)
    integer(i8) :: shapes(4, ARENA_ARRAYS)
    integer(i8) :: c, b, nscale, nblocked
    c = s%ncell
    b = s%nblock
    nscale = 0
    if (s%mass_scaling) nscale = c
    nblocked = 0
    if (b > 0) nblocked = c
    shapes = 1
    shapes(1, 1) = ARENA_SIZES
    shapes(1:2, 2) = [int(s%dim, i8), int(s%nnode, i8)]             ! u
    shapes(1:2, 3) = [int(CELL_MAX_NODES, i8), c]                    ! nodes
    shapes(1, 4:6) = c                                               ! nnodes, weight, material
    shapes(1:2, 7) = [2_i8, c]                                       ! lame
    shapes(1, 8) = c                                                 ! cell_element
    shapes(1:3, 9) = [int(s%dim, i8), int(CELL_MAX_NODES, i8), c]    ! cell_force
    shapes(1:3, 10) = [1_i8, int(CELL_MAX_NODES, i8), nscale]        ! added
    shapes(1:2, 11) = [int(CELL_MAX_NODES, i8), nscale]              ! share
    shapes(1, 12) = b + 1                                            ! block_start
    shapes(1, 13) = b                                                ! block_nodes
    shapes(1, 14:16) = nblocked                                      ! block_cell, cell_block,
                                                                     ! cell_slot
    shapes(:, 17) = [int(BLOCK_CELLS, i8), 3_i8, int(CELL_MAX_NODES, i8), b]   ! block_grad
    shapes(1:3, 18) = [int(BLOCK_CELLS, i8), int(METRIC_ENTRIES, i8), b]  ! block_w0
    shapes(1:2, 19) = [int(BLOCK_CELLS, i8), b]                      ! block_weight
    shapes(1:3, 20) = [int(BLOCK_CELLS, i8), int(NHIST, i8), b]      ! block_hist
    shapes(1:2, 21) = [int(BLOCK_CELLS, i8), b]                      ! block_omega0
  end function arena_shapes

  !> Point the arena's arrays at the addresses given, with arena_shapes' shapes.
  subroutine associate_arrays(s, address_of)
    type(explicit_state_t), intent(inout) :: s        !< state or view (sizes set)
    type(c_ptr), intent(in) :: address_of(ARENA_ARRAYS)  !< address of each array
    integer(i8) :: shapes(4, ARENA_ARRAYS)
    shapes = arena_shapes(s)
    call c_f_pointer(address_of(2), s%u, shapes(1:2, 2))
    call c_f_pointer(address_of(3), s%nodes, shapes(1:2, 3))
    call c_f_pointer(address_of(4), s%nnodes, shapes(1:1, 4))
    call c_f_pointer(address_of(5), s%weight, shapes(1:1, 5))
    call c_f_pointer(address_of(6), s%material, shapes(1:1, 6))
    call c_f_pointer(address_of(7), s%lame, shapes(1:2, 7))
    call c_f_pointer(address_of(8), s%cell_element, shapes(1:1, 8))
    call c_f_pointer(address_of(9), s%cell_force, shapes(1:3, 9))
    call c_f_pointer(address_of(10), s%added, shapes(1:3, 10))
    call c_f_pointer(address_of(11), s%share, shapes(1:2, 11))
    call c_f_pointer(address_of(12), s%block_start, shapes(1:1, 12))
    call c_f_pointer(address_of(13), s%block_nodes, shapes(1:1, 13))
    call c_f_pointer(address_of(14), s%block_cell, shapes(1:1, 14))
    call c_f_pointer(address_of(15), s%cell_block, shapes(1:1, 15))
    call c_f_pointer(address_of(16), s%cell_slot, shapes(1:1, 16))
    call c_f_pointer(address_of(17), s%block_grad, shapes(1:4, 17))
    call c_f_pointer(address_of(18), s%block_w0, shapes(1:3, 18))
    call c_f_pointer(address_of(19), s%block_weight, shapes(1:2, 19))
    call c_f_pointer(address_of(20), s%block_hist, shapes(1:3, 20))
    call c_f_pointer(address_of(21), s%block_omega0, shapes(1:2, 21))
  end subroutine associate_arrays

end module mefem_explicit_state
