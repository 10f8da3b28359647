!> The cell loop of the explicit solver: per cell the smoothed F, the material update, the
!> nodal force contributions and the cell's stable step, and their assembly into f_int_new.
!>
!> 3D cells are computed in blocks of up to BLOCK_CELLS cells of one material and node count
!> (build_blocks, block_forces: structure-of-arrays kernels vectorised across the cells), all
!> of them in ascending cell order; 2D cells one by one (cell_forces). Then the halo exchange
!> of the sums other ranks need starts.
!>
!> Assembly per chunk in ascending global cell order, then over the chunks in chunk order
!> (mefem_explicit_layout), so that forces have the same bits on any number of ranks: in 3D,
!> a contribution is added at once to its column (its node's, or its node's partial sum of
!> the cell's chunk) when the blocks reach that column's cells in ascending order (pushed
!> assembly: plan_pushed_assembly); the others are stored per cell and summed by mefem_halo.
module mefem_explicit_cell_forces
  use mefem_kinds, only: wp, i1
  use mefem_errors, only: status_t
  use mefem_strings, only: itoa
  use mefem_model, only: model_t, material_t
  use mefem_halo, only: halo_t, halo_assemble, halo_assemble_start, halo_assembly_push_nodes, &
                        halo_assemble_summed
  use mefem_cells, only: cells_t, CELL_MAX_NODES, MEFEM_FACE_NODES, cell_grad_column
  use mefem_hexahedron, only: HOURGLASS_MODES, HOURGLASS_VECTORS, block_hourglass_forces, &
                              block_hexahedron_frequency
  use mefem_cell_finite_strain, only: cell_deformation_gradient, cell_internal_force, &
                                      block_deformation_gradient, block_adjugate, &
                                      block_internal_force, adjugate_3x3, block_strain_rate, &
                                      block_face_deformation_gradient, &
                                      block_face_internal_force, face_gradients_compact, &
                                      face_gradients_expanded, FACE_COMPACT_COLUMNS, &
                                      inverse_3x3
  use mefem_stable_time_step, only: cell_critical_omega_squared, block_critical_omega_squared, &
                                    cell_split_weights, inverse_mass_metric, &
                                    cell_rebalance_weights, metric_packed, metric_unpacked, &
                                    cell_reference_bound, block_quick_omega_squared
  use mefem_material_state, only: NHIST, HIST_ALPHA, HIST_DAMAGE, material_state_init, &
                                  BLOCK_CELLS => BLOCK_POINTS
  use mefem_material_update, only: material_update, material_update_block, rate_dependent, &
                                   material_fails, failed_point_energy, point_fails
  use mefem_tensor_algebra, only: determinant, inverse_cube_root
  use mefem_explicit_state, only: explicit_state_t, set_to_zero, state_peer_view
  use mefem_comm, only: comm_rank, comm_size, comm_barrier, comm_arena_free, comm_arena_sync, &
                        comm_work_reset, &
                        comm_work_take, comm_work_steal, comm_work_finished, comm_work_wait
  implicit none
  private

  public :: explicit_cells_set_up, explicit_cell_loop, block_cell_data, explicit_blocks_group
  public :: explicit_mass_split, volume_scale, nodal_reference_volumes, set_cell_metric
  public :: explicit_steal_set_up, explicit_steal_tear_down

  !> Rebalancing passes of the stiffness-weighted mass split (explicit_mass_split; doc/theory.md
  !> 7): each multiplies a cell's shares by its bound omega_c^2, so the mass moves towards the
  !> cells that set the step (fixed point: equal bounds in the cells that share a node). Not
  !> with mass scaling (DT2MS < 0: the step is the user's, the split only places the added
  !> mass, and the passes raised the main example's added mass from 11.0 to 12.5 %).
  !> Copper Taylor bar, 4 860 ME-FEM tets: 7 647 cycles without passes, 6 748 / 6 554 / 6 498
  !> with 2 / 4 / 8 (ELFORM 10: 5 387 -> 5 051 with 4); shares times omega_c^4 oscillate.
  integer, parameter :: SPLIT_PASSES = 4

  !> The quick step bound (block_quick_omega_squared; doc/theory.md 7) is taken by a cell whose
  !> quick step is above QUICK_STEP_MARGIN times the last cycle's stable step, the exact bound
  !> computed for the others: the smallest step is then exact as long as it grows by less than
  !> this factor from one cycle to the next (a cell's step changes by the strain of one cycle,
  !> ~1e-3; every cell is exact after a new mass split, which can raise it by more); after a
  !> larger jump (the controlling cell eroded, a step cap lifted) the step is the quick
  !> bound's for a few cycles, conservative, and the margin takes it back up.
  real(wp), parameter :: QUICK_STEP_MARGIN = 1.1_wp

contains

  !> 3D: group the local cells into blocks (with their gradients, metrics, volumes and
  !> virgin histories) and plan the pushed assembly (telling the halo which nodes it is).
  subroutine explicit_cells_set_up(s, cells, w0, halo, starts, nodes_of, order)
    type(explicit_state_t), intent(inout) :: s        !< local state (cells set up)
    type(cells_t), intent(in) :: cells                !< all cells (gradients)
    real(wp), intent(in) :: w0(:,:,:)                 !< (3, 3, s%ncell) local cells' metrics
    type(halo_t), intent(inout) :: halo               !< force exchange
    integer, intent(in) :: starts(:), nodes_of(:), order(:)  !< explicit_blocks_group's
    character(len=8) :: value
    integer :: length, status
    call build_blocks(s, cells, w0, starts, nodes_of, order)
    call get_environment_variable('MEFEM_EXACT_STEPS', value, length, status)
    s%exact_steps = status == 0 .and. trim(value) == '1'
    call hourglass_set_up(s, cells)
    call nodal_pressure_set_up(s, cells, halo)
    call plan_pushed_assembly(s, halo)
  end subroutine explicit_cells_set_up

  !> All local cells at the current displacements: internal forces into f_int_new (the
  !> sums of this rank's chunks; the halo exchange of those other ranks need is started here
  !> and finished by the caller), the smallest stable step (dt_stable, dt_element) and the
  !> first failure (failed, failure).
  !>
  !> 3D: the blocks in ascending cell order (with the other ranks of the node taking some of
  !> them: blocks_shared_with_node), then the exchange. Computing the cells next to other
  !> ranks first so that the exchange overlaps the others was measured slower
  !> (doc/performance.md, "How the cycle is organised"): the ranks meet at the exchange
  !> anyway.
  subroutine explicit_cell_loop(model, s, halo, dt_last)
    type(model_t), intent(in) :: model                !< resolved model
    type(explicit_state_t), intent(inout) :: s        !< local state
    type(halo_t), intent(inout) :: halo               !< force exchange (started here)
    real(wp), intent(in) :: dt_last                   !< the last cycle's stable step (0: none,
                                                      !< every cell's exact bound)
    integer :: k, own, l
    ! (every cell exact at the first evaluation and after a new mass split, whose metrics can
    ! raise the smallest step by more than the margin)
    s%exact_step_below = huge(1.0_wp)
    if (dt_last > 0.0_wp .and. .not. (s%exact_steps .or. s%new_split)) &
      s%exact_step_below = QUICK_STEP_MARGIN*dt_last
    s%new_split = .false.
    s%bound_blocks = s%bound_blocks + s%nblock
    s%dt_stable = huge(1.0_wp)
    s%dt_element = 0
    s%failed = .false.
    s%hourglass_stored = 0.0_wp
    s%hourglass_power = 0.0_wp
    if (s%nblock > 0 .or. s%ncell == 0) then
      if (allocated(s%push_node)) call set_to_zero(size(s%f_int_new), s%f_int_new)
      if (s%nodal_pressure) call nodal_volumes(s, halo)
      if (size(s%peers) == 0) then
        do k = 1, s%nblock
          call block_forces(model, s, k, .false.)
        end do
      else
        call blocks_shared_with_node(model, s, own)
        call add_stolen_blocks(s, own)
      end if
      if (s%nodal_pressure) call nodal_pressure_forces(s, halo)
      call halo_assemble_start(halo, s%cell_force, s%f_int_new, pushed=allocated(s%push_node))
    else
      do l = 1, s%ncell
        call cell_forces(model, s, l)
      end do
      call halo_assemble_start(halo, s%cell_force, s%f_int_new)
    end if
    if (s%erosion) call collect_failed_cells(model, s)
  end subroutine explicit_cell_loop

  !> Erosion: this rank's cells that failed this cycle (by their mark, HIST_ALPHA < 0, also
  !> where another rank of the node computed them) are listed by global index in new_eroded
  !> and their internal energy (failed_point_energy times V0) added to eroded_energy.
  subroutine collect_failed_cells(model, s)
    type(model_t), intent(in) :: model                !< resolved model
    type(explicit_state_t), intent(inout) :: s        !< local state
    integer, allocatable :: grown(:)
    logical, allocatable :: marked(:)
    real(wp) :: alpha
    integer :: l, b
    ! 3D: the blocks that hold a mark at all (one vector test each; most hold none)
    allocate(marked(s%nblock))
    do b = 1, s%nblock
      marked(b) = any(s%block_hist(1:s%block_start(b + 1) - s%block_start(b), HIST_ALPHA, b) < &
                      0.0_wp)
    end do
    if (s%nblock > 0) then
      if (.not. any(marked)) return
    end if
    do l = 1, s%ncell
      if (s%cell_counted(l)) cycle
      if (s%nblock > 0) then
        if (.not. marked(s%cell_block(l))) cycle
      end if
      if (.not. material_fails(model%materials(s%material(l)))) cycle
      if (.not. cell_failed(s, l)) cycle
      if (s%nblock > 0) then
        alpha = s%block_hist(s%cell_slot(l), HIST_ALPHA, s%cell_block(l))
      else
        alpha = s%hist(HIST_ALPHA, l)
      end if
      s%cell_counted(l) = .true.
      if (s%n_new_eroded == size(s%new_eroded)) then
        allocate(grown(max(16, 2*s%n_new_eroded)))
        grown(1:s%n_new_eroded) = s%new_eroded(1:s%n_new_eroded)
        call move_alloc(grown, s%new_eroded)
      end if
      s%n_new_eroded = s%n_new_eroded + 1
      s%new_eroded(s%n_new_eroded) = s%cell_global(l)
      s%eroded_energy = s%eroded_energy + s%weight(l)* &
          failed_point_energy(model%materials(s%material(l)), model%curves, -alpha)
    end do
  end subroutine collect_failed_cells

  !> 3D blocks with the other ranks of this node (work stealing): this rank takes its blocks
  !> in chunks from the front (mefem_comm's comm_work_take) and, when none are left, takes
  !> chunks from the back of the others' blocks and computes them through their views
  !> (block_forces with every contribution stored in the owner's cell array, its histories
  !> updated in place); then it waits until the others have finished the blocks they took of
  !> its own (blocks own+1..nblock: add_stolen_blocks adds their pushed contributions). The
  !> smallest step and a failure found in another rank's cells count as this rank's.
  subroutine blocks_shared_with_node(model, s, own)
    type(model_t), intent(in) :: model                !< resolved model
    type(explicit_state_t), intent(inout) :: s        !< local state (peers set up)
    integer, intent(out) :: own                       !< blocks 1..own computed here
    integer, parameter :: OWN_CHUNK = 8               !< blocks per claim of one's own
    integer, parameter :: STEAL_CHUNK = 4             !< blocks per claim of another's
    integer :: first, last, k, j
    logical :: took
    call comm_work_reset(s%arena, s%nblock, OWN_CHUNK)
    own = 0
    if (s%steal_test) then
      call take_own(s%nblock/2)         ! tests: the others' blocks before the second half
    else
      call take_own(s%nblock)
    end if
    ! the others' blocks, from their backs, until none is left anywhere
    do
      took = .false.
      do j = 1, size(s%peers)
        call comm_work_steal(s%arena, s%peer_rank(j), STEAL_CHUNK, first, last)
        if (last < first) cycle
        took = .true.
        s%peers(j)%dt_stable = huge(1.0_wp)
        s%peers(j)%dt_element = 0
        s%peers(j)%time = s%time
        s%peers(j)%dt_step = s%dt_step
        s%peers(j)%exact_step_below = s%exact_step_below
        s%peers(j)%failed = .false.
        do k = first, last
          call block_forces(model, s%peers(j), k, .true.)
        end do
        call comm_work_finished(s%arena, s%peer_rank(j), last - first + 1)
        s%blocks_for_others = s%blocks_for_others + (last - first + 1)
        s%exact_bound_blocks = s%exact_bound_blocks + s%peers(j)%exact_bound_blocks
        s%peers(j)%exact_bound_blocks = 0
        call keep_smaller_step(model, s, s%peers(j)%dt_stable, s%peers(j)%dt_element)
        if (s%peers(j)%failed .and. .not. s%failed) then
          s%failed = .true.
          s%failure = s%peers(j)%failure
        end if
      end do
      if (.not. took) exit
    end do
    call take_own(s%nblock)             ! (tests: what the others left of the second half)
    ! this rank's blocks the others took: wait for them, then their pushed contributions
    call comm_work_wait(s%arena, s%nblock - own)
    s%blocks_by_others = s%blocks_by_others + (s%nblock - own)
  contains

    !> Own blocks from the front, chunk by chunk, until `limit` is passed or none is left
    !> (the blocks taken are 1..own: the front only moves forward).
    subroutine take_own(limit)
      integer, intent(in) :: limit                    !< stop once own >= limit
      do while (own < limit)
        call comm_work_take(s%arena, first, last)
        if (last < first) exit
        do k = first, last
          call block_forces(model, s, k, .false.)
        end do
        own = last
      end do
    end subroutine take_own

  end subroutine blocks_shared_with_node

  !> The pushed contributions of this rank's blocks own+1..nblock, which other ranks of the
  !> node computed (stored in the cell array), added in block order after this rank's own
  !> pass: the additions that pass would have made, in its order (the same bits).
  subroutine add_stolen_blocks(s, own)
    type(explicit_state_t), intent(inout) :: s        !< local state
    integer, intent(in) :: own                        !< blocks computed by this rank
    integer :: k, m, l, a, node
    if (.not. allocated(s%push_node)) return
    do k = own + 1, s%nblock
      do m = s%block_start(k), s%block_start(k + 1) - 1
        l = s%block_cell(m)
        do a = 1, s%nnodes(l)
          node = s%push_node(a, l)
          if (node == 0) cycle
          s%f_int_new(1, node) = s%f_int_new(1, node) + s%cell_force(1, a, l)
          s%f_int_new(2, node) = s%f_int_new(2, node) + s%cell_force(2, a, l)
          s%f_int_new(3, node) = s%f_int_new(3, node) + s%cell_force(3, a, l)
        end do
      end do
    end do
  end subroutine add_stolen_blocks

  !> Views of the other ranks of this node, for blocks_shared_with_node (3D; collective: every
  !> rank's arena must hold its sizes, so call it after every rank's set-up of its cells).
  subroutine explicit_steal_set_up(s)
    type(explicit_state_t), intent(inout) :: s        !< local state (arena filled)
    type(explicit_state_t), allocatable :: views(:)
    integer, allocatable :: ranks(:)
    integer :: r, n
    logical :: ok
    character(len=8) :: value
    integer :: length, status
    call comm_arena_sync(s%arena)
    call comm_barrier()                               ! every arena's sizes written
    call comm_arena_sync(s%arena)
    allocate(views(comm_size()), ranks(comm_size()))
    n = 0
    ! (ELFORM 13 cells need the nodal sums between the blocks and their forces, hexahedra
    ! their hourglass data and the velocities, which the views do not hold: no stealing)
    if (s%dim == 3 .and. .not. s%nodal_pressure .and. .not. s%hourglass) then
      do r = 0, comm_size() - 1
        if (r == comm_rank()) cycle
        call state_peer_view(s, r, views(n + 1), ok)
        if (.not. ok) cycle
        if (views(n + 1)%dim /= 3) cycle
        n = n + 1
        ranks(n) = r
      end do
    end if
    s%peers = views(1:n)                              ! (pointer components: the same arrays)
    s%peer_rank = ranks(1:n)
    call get_environment_variable('MEFEM_STEAL_TEST', value, length, status)
    s%steal_test = status == 0 .and. trim(value) == '1' .and. comm_rank() == 0 .and. n > 0
  end subroutine explicit_steal_set_up

  !> Release the node-shared arena (collective; at the end of the run).
  subroutine explicit_steal_tear_down(s)
    type(explicit_state_t), intent(inout) :: s        !< local state
    if (allocated(s%peers)) deallocate(s%peers)
    call comm_arena_free(s%arena)
  end subroutine explicit_steal_tear_down

  !> Keep a step (of one cell, or the smallest of another rank's cells computed here) if it
  !> is smaller than the smallest so far; among equal steps, the lower element id.
  subroutine keep_smaller_step(model, s, dt, element)
    type(model_t), intent(in) :: model                !< resolved model
    type(explicit_state_t), intent(inout) :: s        !< local state
    real(wp), intent(in) :: dt                        !< the step
    integer, intent(in) :: element                    !< its element (0: none)
    if (element == 0) return
    if (dt < s%dt_stable) then
      s%dt_stable = dt
      s%dt_element = element
    else if (dt == s%dt_stable .and. s%dt_element > 0) then
      if (model%elements%id(element) < model%elements%id(s%dt_element)) s%dt_element = element
    end if
  end subroutine keep_smaller_step

  !> One cell: smoothed F, material update (history committed at once: explicit), the
  !> nodal force contributions and the cell's stable step (with added mass if scaling). The
  !> cell's data come from the blocks (3D) or the per-cell arrays (2D).
  subroutine cell_forces(model, s, l)
    type(model_t), intent(in) :: model                !< resolved model
    type(explicit_state_t), intent(inout) :: s        !< local state
    integer, intent(in) :: l                          !< local cell
    real(wp) :: grad(3, CELL_MAX_NODES), w0(3, 3), hist_old(NHIST)
    if (s%nblock > 0) then
      call block_cell_data(s, l, grad, w0, hist_old)
      call cell_evaluate(model, s, l, grad, w0, hist_old)
    else
      hist_old = s%hist(:, l)
      call cell_evaluate(model, s, l, s%grad(:, :, l), s%w0(:, :, l), hist_old)
    end if
  end subroutine cell_forces

  !> Gradients, metric and history of local cell l from the block storage (3D).
  subroutine block_cell_data(s, l, grad, w0, hist)
    type(explicit_state_t), intent(in) :: s           !< local state (3D, blocks built)
    integer, intent(in) :: l                          !< local cell
    real(wp), intent(out) :: grad(3, CELL_MAX_NODES)  !< reference gradients
    real(wp), intent(out) :: w0(3, 3)                 !< inverse-mass metric
    real(wp), intent(out) :: hist(NHIST)              !< history
    integer :: b, i
    b = s%cell_block(l)
    i = s%cell_slot(l)
    call block_cell_gradients(s, l, grad)
    w0 = metric_unpacked(s%block_w0(i, :, b))
    hist = s%block_hist(i, :, b)
  end subroutine block_cell_data

  !> The reference gradients of local cell l from the block storage (3D): an ME-FEM face
  !> cell's expanded from their compact form (face_gradients_expanded).
  subroutine block_cell_gradients(s, l, grad)
    type(explicit_state_t), intent(in) :: s           !< local state (3D, blocks built)
    integer, intent(in) :: l                          !< local cell
    real(wp), intent(out) :: grad(3, CELL_MAX_NODES)  !< reference gradients
    integer :: b, i
    b = s%cell_block(l)
    i = s%cell_slot(l)
    if (s%block_nodes(b) == MEFEM_FACE_NODES) then
      grad = 0.0_wp
      grad(:, 1:MEFEM_FACE_NODES) = face_gradients_expanded(s%nnodes(l), &
          s%block_grad(i, :, 1:FACE_COMPACT_COLUMNS, b))
    else
      grad = s%block_grad(i, :, :, b)
    end if
  end subroutine block_cell_gradients

  !> Store the inverse-mass metric W0 of local cell l in the blocks (3D), packed
  !> (metric_packed), with the quick step bound's factor cell_reference_bound.
  subroutine set_cell_metric(s, l, w0)
    type(explicit_state_t), intent(inout) :: s        !< local state (3D, blocks built)
    integer, intent(in) :: l                          !< local cell
    real(wp), intent(in) :: w0(3, 3)                  !< its metric
    s%block_w0(s%cell_slot(l), :, s%cell_block(l)) = metric_packed(w0)
    s%block_omega0(s%cell_slot(l), s%cell_block(l)) = cell_reference_bound(w0, s%lame(1, l), &
                                                                           s%lame(2, l))
  end subroutine set_cell_metric

  !> The work of cell_forces on the cell's data; the new history is stored (blocks or
  !> per-cell array) once the material update succeeded.
  subroutine cell_evaluate(model, s, l, grad, w0, hist_old)
    type(model_t), intent(in) :: model                !< resolved model
    type(explicit_state_t), intent(inout) :: s        !< local state
    integer, intent(in) :: l                          !< local cell
    real(wp), intent(in), contiguous :: grad(:,:)     !< (dim, CELL_MAX_NODES) gradients
    real(wp), intent(in), contiguous :: w0(:,:)       !< (dim, dim) inverse-mass metric
    real(wp), intent(in) :: hist_old(NHIST)           !< history at t_n
    real(wp) :: ue(3, CELL_MAX_NODES), f(3, 3), tau(3, 3), hist_new(NHIST), sound, omega2
    real(wp) :: fbar(3, 3), det, jbar, adjugate(3, 3), rate
    type(status_t) :: status
    integer :: nn, dim, k
    logical :: averaged
    dim = s%dim
    nn = s%nnodes(l)
    if (hist_old(HIST_ALPHA) < 0.0_wp) then      ! a failed cell (erosion): no force, no step
      s%cell_force(:, 1:nn, l) = 0.0_wp
      if (s%nodal_pressure) then
        if (s%np_cell(l)) then
          s%np_area(:, :, l) = 0.0_wp
          s%np_pressure(l) = 0.0_wp
          s%np_deviator(:, l) = 0.0_wp
        end if
      end if
      if (s%mass_scaling) s%added(1, 1:nn, l) = 0.0_wp       ! (bounds no step)
      return
    end if
    do k = 1, nn                 ! gather by a loop (a vector subscript allocates a temporary)
      ue(1:dim, k) = s%u(1:dim, s%nodes(k, l))
    end do
    call cell_deformation_gradient(dim, nn, grad, ue(1:dim, 1:nn), f)
    rate = 0.0_wp
    if (rate_dependent(model%materials(s%material(l)))) rate = cell_strain_rate(s, l, grad, f, &
        model%materials(s%material(l))%vp < 0.0_wp)
    jbar = 1.0_wp
    averaged = s%nodal_pressure
    if (averaged) averaged = s%np_cell(l)
    if (averaged) then                        ! as block_forces, one cell
      det = determinant(f)
      jbar = element_mean_j(s, l, det)
      jbar = merge(jbar, det, det > 0.0_wp .and. jbar > 0.0_wp)
      fbar = f*volume_scale(jbar, det)
      call material_update(model%materials(s%material(l)), model%curves, fbar, hist_old, &
                           hist_new, tau, sound_speed=sound, status=status, strain_rate=rate, &
                           dt=s%dt_step, spall=.true.)
      if (status%ok) then
        call split_pressure(tau(1, 1), tau(2, 2), tau(3, 3), jbar, s%np_pressure(l))
        s%np_jbar(l) = jbar
        call adjugate_3x3(f, adjugate, det)
        s%np_deviator(:, l) = [tau(1, 1), tau(2, 2), tau(3, 3), tau(1, 2), tau(2, 3), &
                               tau(1, 3)]/det
        call keep_area_vectors(s, l, grad(:, 1:4), reshape(adjugate, [9]))
      end if
    else
      call material_update(model%materials(s%material(l)), model%curves, f, hist_old, &
                           hist_new, tau, sound_speed=sound, status=status, strain_rate=rate, &
                           dt=s%dt_step, spall=.true.)
    end if
    if (.not. status%ok) then
      s%cell_force(:, :, l) = 0.0_wp
      if (.not. s%failed) s%failure = 'element '// &
          itoa(model%elements%id(first_element(s, l)))//': '//trim(status%message)
      s%failed = .true.
      return
    end if
    if (material_fails(model%materials(s%material(l)))) then
      if (cell_fails_now(model%materials(s%material(l)))) then
        hist_new(HIST_ALPHA) = -max(hist_new(HIST_ALPHA), tiny(1.0_wp))   ! fails (erosion)
        tau = 0.0_wp
        if (averaged) then
          s%np_pressure(l) = 0.0_wp
          s%np_deviator(:, l) = 0.0_wp
          s%np_area(:, :, l) = 0.0_wp
        end if
      end if
    end if
    if (s%nblock > 0) then
      s%block_hist(s%cell_slot(l), :, s%cell_block(l)) = hist_new
    else
      s%hist(:, l) = hist_new
    end if
    ! (an ELFORM 13 cell's forces follow in nodal_pressure_forces)
    if (.not. averaged) call cell_internal_force(dim, nn, grad, s%weight(l), f, tau, &
                                                 s%cell_force(:, 1:nn, l))
    omega2 = cell_critical_omega_squared(dim, s%weight(l), w0, f, s%lame(1, l), s%lame(2, l))
    call take_cell_step(model, s, l, omega2)

  contains

    !> The cell fails now (point_fails at the stress's J: the cell's, or Jbar for ELFORM 13).
    logical function cell_fails_now(mat)
      type(material_t), intent(in) :: mat             !< the cell's material
      real(wp) :: tau6(6)
      tau6 = [tau(1, 1), tau(2, 2), tau(3, 3), tau(1, 2), tau(2, 3), tau(1, 3)]
      cell_fails_now = point_fails(mat, hist_new(HIST_ALPHA), hist_new(HIST_DAMAGE), &
                                   reshape(f, [9]), tau6, merge(jbar, determinant(f), averaged), &
                                   s%time)
    end function cell_fails_now

  end subroutine cell_evaluate

  !> Effective strain rate of local cell l (as block_strain_rate, one cell, 2D or 3D): d =
  !> sym(Fdot F^-1), Fdot = sum_a v_a (x) grad_a, the rate sqrt(d : d) (deviatoric: of dev d).
  real(wp) function cell_strain_rate(s, l, grad, f, deviatoric) result(rate)
    type(explicit_state_t), intent(in) :: s           !< local state
    integer, intent(in) :: l                          !< local cell
    real(wp), intent(in), contiguous :: grad(:,:)     !< (dim, CELL_MAX_NODES) gradients
    real(wp), intent(in) :: f(3, 3)                   !< its F
    logical, intent(in) :: deviatoric                 !< the deviatoric rate (VP = -1)
    real(wp) :: fdot(3, 3), finv(3, 3), d(3, 3), det, mean
    integer :: a, dim
    dim = s%dim
    fdot = 0.0_wp
    do a = 1, s%nnodes(l)
      fdot(1:dim, 1:dim) = fdot(1:dim, 1:dim) + spread(s%v(:, s%nodes(a, l)), 2, dim)* &
                           spread(grad(1:dim, a), 1, dim)
    end do
    call inverse_3x3(f, finv, det)
    d = matmul(fdot, finv)
    d = 0.5_wp*(d + transpose(d))
    if (deviatoric) then
      mean = (d(1, 1) + d(2, 2) + d(3, 3))/3.0_wp
      do a = 1, 3
        d(a, a) = d(a, a) - mean
      end do
    end if
    rate = sqrt(sum(d*d))
  end function cell_strain_rate

  !> A cell's stable step 2/omega from its bound omega^2 (a NaN or overflow fails the cell),
  !> with the mass added if scaling, times TSSFAC; the smallest is kept with its cell, among
  !> equal steps the cell of the lowest element id (independent of the order in which cells
  !> are computed).
  subroutine take_cell_step(model, s, l, omega2)
    type(model_t), intent(in) :: model                !< resolved model
    type(explicit_state_t), intent(inout) :: s        !< local state
    integer, intent(in) :: l                          !< local cell
    real(wp), intent(in) :: omega2                    !< its bound of omega^2
    real(wp) :: dt_cell, target, factor
    integer :: nn
    if (.not. (omega2 >= 0.0_wp .and. omega2 < huge(1.0_wp))) then     ! NaN or overflow
      if (.not. s%failed) s%failure = 'element '// &
          itoa(model%elements%id(first_element(s, l)))//': the stable time step is not a '// &
          'number (NaN or infinite deformation)'
      s%failed = .true.
      return
    end if
    dt_cell = 2.0_wp/sqrt(max(omega2, tiny(1.0_wp)))
    if (s%mass_scaling) then
      nn = s%nnodes(l)
      target = abs(model%controls%dt2ms)
      factor = 0.0_wp
      if (dt_cell < target) then
        factor = (target/dt_cell)**2 - 1.0_wp
        dt_cell = target
      end if
      s%added(1, 1:nn, l) = factor*s%share(1:nn, l)
    end if
    dt_cell = model%controls%tssfac*dt_cell
    call keep_smallest_step(model, s, l, dt_cell)
  end subroutine take_cell_step

  !> Keep dt_cell of local cell l if it is the smallest step so far (among equal steps, the
  !> cell of the lowest element id).
  subroutine keep_smallest_step(model, s, l, dt_cell)
    type(model_t), intent(in) :: model                !< resolved model
    type(explicit_state_t), intent(inout) :: s        !< local state
    integer, intent(in) :: l                          !< local cell
    real(wp), intent(in) :: dt_cell                   !< its step (TSSFAC applied)
    call keep_smaller_step(model, s, dt_cell, s%cell_element(l))
  end subroutine keep_smallest_step

  !> Group the local cells into blocks for block_forces (3D; before the arena, which they
  !> size): cells of equal (material, node count, nodal pressure, hexahedron) together in
  !> ascending cell
  !> order, cut into blocks of at most BLOCK_CELLS. Block b holds cells
  !> order(starts(b):starts(b+1)-1),
  !> computed with nodes_of(b) nodes (size(nodes_of) blocks). The order of computation does
  !> not change any result: every cell writes its own contributions and the assembly order
  !> is fixed by the layout's plan.
  subroutine explicit_blocks_group(material, nnodes, nodal_pressure, hexahedral, starts, &
                                   nodes_of, order)
    integer, intent(in) :: material(:)                !< (ncell) material of each cell
    integer, intent(in) :: nnodes(:)                  !< (ncell) nodes of each cell
    logical, intent(in) :: nodal_pressure(:)          !< (ncell) an ELFORM 13 cell
    logical, intent(in) :: hexahedral(:)              !< (ncell) a hexahedral cell (ELFORM 1)
    integer, allocatable, intent(out) :: starts(:)    !< (nblock+1) offsets into order
    integer, allocatable, intent(out) :: nodes_of(:)  !< (nblock) node count of each block
    integer, allocatable, intent(out) :: order(:)     !< (ncell) cells, block by block
    logical :: placed(size(material))
    integer :: k, m, n, placed_count, key_material, key_nodes, in_block, nblock
    logical :: key_pressure
    n = size(material)
    allocate(starts(n + 2), nodes_of(n + 1), order(n))
    nblock = 0
    starts(1) = 1
    placed = .false.
    placed_count = 0
    do k = 1, n
      if (placed(k)) cycle
      key_material = material(k)
      key_nodes = block_node_count(nnodes(k), hexahedral(k))
      key_pressure = nodal_pressure(k)
      in_block = 0
      do m = k, n
        if (placed(m)) cycle
        if (material(m) /= key_material .or. &
            block_node_count(nnodes(m), hexahedral(m)) /= key_nodes .or. &
            (nodal_pressure(m) .neqv. key_pressure)) cycle
        if (in_block == BLOCK_CELLS) then
          nblock = nblock + 1
          starts(nblock + 1) = placed_count + 1
          nodes_of(nblock) = key_nodes
          in_block = 0
        end if
        placed(m) = .true.
        placed_count = placed_count + 1
        order(placed_count) = m
        in_block = in_block + 1
      end do
      nblock = nblock + 1
      starts(nblock + 1) = placed_count + 1
      nodes_of(nblock) = key_nodes
    end do
    starts = starts(1:nblock + 1)
    nodes_of = nodes_of(1:nblock)
  end subroutine explicit_blocks_group

  !> Fill the blocks (arena arrays sized by explicit_blocks_group's grouping): their cells,
  !> the cells' gradients, metrics, volumes and virgin histories (unused entries zero).
  subroutine build_blocks(s, cells, w0, starts, nodes_of, order)
    type(explicit_state_t), intent(inout) :: s        !< local state (cells set up)
    type(cells_t), intent(in) :: cells                !< all cells (gradients)
    real(wp), intent(in) :: w0(:,:,:)                 !< (3, 3, s%ncell) local cells' metrics
    integer, intent(in) :: starts(:), nodes_of(:), order(:)  !< explicit_blocks_group's
    integer :: b, k, l, i, c
    s%block_start = starts
    s%block_nodes = nodes_of
    s%block_cell = order
    s%block_grad = 0.0_wp
    s%block_w0 = 0.0_wp
    s%block_omega0 = 0.0_wp
    s%block_weight = 0.0_wp
    s%block_hist = 0.0_wp
    do b = 1, s%nblock
      do k = s%block_start(b), s%block_start(b + 1) - 1
        l = s%block_cell(k)
        i = k - s%block_start(b) + 1
        c = s%cell_global(l)
        s%cell_block(l) = b
        s%cell_slot(l) = i
        if (s%block_nodes(b) == MEFEM_FACE_NODES) then   ! compact (face_gradients_compact)
          s%block_grad(i, :, 1:FACE_COMPACT_COLUMNS, b) = face_gradients_compact( &
              cells%grad(:, 1:MEFEM_FACE_NODES, cell_grad_column(cells, c)))
        else
          s%block_grad(i, :, :, b) = cells%grad(:, :, cell_grad_column(cells, c))
        end if
        call set_cell_metric(s, l, w0(:, :, l))
        s%block_weight(i, b) = s%weight(l)
        call material_state_init(s%block_hist(i, :, b))
      end do
    end do
  end subroutine build_blocks

  !> Number of nodes a 3D cell is computed with in the blocks: an ME-FEM face cell (more than
  !> the 4 corners of a tet: 5 on the boundary, 7 inside) as a MEFEM_FACE_NODES-node cell, a
  !> hexahedral cell (a pentahedron's 6 nodes too) as an 8-node cell, their missing nodes with
  !> zero gradients (they add exact zeros to F and get no force), so that the cells of a part
  !> form one sequence of blocks in ascending cell order and the pushed assembly reaches the
  !> nodes of the boundary too; a standard tet cell with its 4 nodes.
  pure integer function block_node_count(nnodes, hexahedral)
    integer, intent(in) :: nnodes                     !< the cell's nodes
    logical, intent(in) :: hexahedral                 !< a hexahedral cell
    if (hexahedral) then
      block_node_count = CELL_MAX_NODES
    else if (nnodes > 4) then
      block_node_count = MEFEM_FACE_NODES
    else
      block_node_count = nnodes
    end if
  end function block_node_count

  !> One block of 3D cells of one material and node count (build_blocks): the steps of
  !> cell_forces with the cells in the inner loops. The block's data are gathered into
  !> structure-of-arrays temporaries (entry i is the block's i-th cell), the kernels run over
  !> the block (vectorised across cells; each cell's arithmetic is cell_forces', so the
  !> results are the same bits), and the forces, histories and step are scattered back. A
  !> cell whose material update fails is redone by cell_forces, which reports it.
  subroutine block_forces(model, s, b, store_all)
    type(model_t), intent(in) :: model                !< resolved model
    type(explicit_state_t), intent(inout) :: s        !< local state, or a view of another
                                                      !< rank's (blocks_shared_with_node)
    integer, intent(in) :: b                          !< block
    logical, intent(in) :: store_all                  !< keep every contribution in the cell
                                                      !< array (another rank's block: its
                                                      !< owner adds the pushed ones)
    integer, parameter :: LD = BLOCK_CELLS
    real(wp) :: u(LD, 3, CELL_MAX_NODES), force(LD, 3, CELL_MAX_NODES)
    real(wp) :: f(LD, 9), adj(LD, 9), det(LD), tau(LD, 6), omega2(LD), dt_block(LD)
    real(wp) :: fbar(LD, 9), jbar(LD), scale(LD)
    real(wp) :: v(LD, 3, CELL_MAX_NODES)
    real(wp) :: stiffness(LD, 6), viscosity(LD), energy(LD), power(LD), c_inverse(6)
    real(wp) :: position(LD, 3, 8), rule(LD), rate(LD), kept(LD, NHIST)
    real(wp) :: omega_exact(LD), exact(LD), limit
    logical :: ok(LD), finite(LD), steps_at_once, averaged, hexahedral, rated, erodes, &
               failed(LD), viscous, face, quick
    integer :: n, nn, i, a, l, node, first, hb, k
    first = s%block_start(b)
    n = s%block_start(b + 1) - first
    if (n == 0) return
    nn = s%block_nodes(b)
    face = nn == MEFEM_FACE_NODES                     ! ME-FEM face cells: compact gradients
    ! gather the displacements (the rest is stored in the blocks; a padded slot, node 0, gets
    ! zero: its gradient is zero, and a boundary face cell's compact F needs the zero)
    do i = 1, n
      l = s%block_cell(first + i - 1)
      do a = 1, nn
        node = s%nodes(a, l)
        if (node > 0) then
          u(i, 1, a) = s%u(1, node)
          u(i, 2, a) = s%u(2, node)
          u(i, 3, a) = s%u(3, node)
        else
          u(i, :, a) = 0.0_wp
        end if
      end do
    end do
    ! F, J and adj(F) once per cell; material update (history in place); forces; stable step
    if (face) then
      call block_face_deformation_gradient(n, u, s%block_grad(:, :, :, b), f)
    else
      call block_deformation_gradient(n, nn, u, s%block_grad(:, :, :, b), f)
    end if
    call block_adjugate(n, f, adj, det)
    l = s%block_cell(first)
    ! erosion: a failed cell (HIST_ALPHA < 0) goes through the kernels at F = I, its history
    ! kept as it is, and carries no stress (erode_failed)
    erodes = material_fails(model%materials(s%material(l)))
    failed(1:n) = .false.
    if (erodes) then
      do i = 1, n
        failed(i) = s%block_hist(i, HIST_ALPHA, b) < 0.0_wp
        if (.not. failed(i)) cycle
        kept(i, :) = s%block_hist(i, :, b)
        f(i, :) = [1.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 1.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 1.0_wp]
        adj(i, :) = f(i, :)
        det(i) = 1.0_wp
      end do
    end if
    ! rate effects of the material (Cowper-Symonds, LCSR): the cells' effective strain rates
    ! from the velocities v^{n+1/2} (the hexahedra's viscous hourglass forces use these too)
    rated = rate_dependent(model%materials(s%material(l)))
    hexahedral = s%hourglass
    if (hexahedral) hexahedral = s%block_hex(b) > 0
    viscous = .false.
    if (hexahedral) viscous = s%hex_viscous(s%block_hex(b))
    if (rated .or. viscous) then                      ! (padded slots: zero, as for u)
      do i = 1, n
        do a = 1, nn
          node = s%nodes(a, s%block_cell(first + i - 1))
          v(i, :, a) = 0.0_wp
          if (node > 0) v(i, :, a) = s%v(:, node)
        end do
      end do
    end if
    if (rated) call block_strain_rate(n, nn, face, v, s%block_grad(:, :, :, b), adj, det, &
                                      model%materials(s%material(l))%vp < 0.0_wp, rate)
    averaged = s%nodal_pressure
    if (averaged) averaged = s%np_cell(l)
    if (averaged) then
      ! nodal-pressure tetrahedra: the material sees Fbar = (Jbar/J)^(1/3) F; the forces take
      ! its deviatoric stress here and the nodally averaged pressure in nodal_pressure_forces
      do i = 1, n
        jbar(i) = element_mean_j(s, s%block_cell(first + i - 1), det(i))
        jbar(i) = merge(jbar(i), det(i), det(i) > 0.0_wp .and. jbar(i) > 0.0_wp)
        if (failed(i)) jbar(i) = 1.0_wp
        scale(i) = volume_scale(jbar(i), det(i))
      end do
      do a = 1, 9
        do i = 1, n
          fbar(i, a) = f(i, a)*scale(i)
        end do
      end do
      if (rated) then
        call material_update_block(model%materials(s%material(l)), model%curves, n, fbar, &
                                   jbar, s%block_hist(:, :, b), tau, ok, rate, s%dt_step)
      else
        call material_update_block(model%materials(s%material(l)), model%curves, n, fbar, &
                                   jbar, s%block_hist(:, :, b), tau, ok)
      end if
      if (erodes) call erode_failed()
      do i = 1, n
        l = s%block_cell(first + i - 1)
        call split_pressure(tau(i, 1), tau(i, 2), tau(i, 3), jbar(i), s%np_pressure(l))
        s%np_jbar(l) = jbar(i)
        do a = 1, 6
          s%np_deviator(a, l) = tau(i, a)/det(i)
        end do
      end do
      ! the area vectors V0 adj(F)^T g_a (keep_area_vectors; cell by cell: each cell's 12
      ! values stored together)
      do i = 1, n
        l = s%block_cell(first + i - 1)
        if (failed(i)) then                  ! no force on a failed cell
          s%np_area(:, :, l) = 0.0_wp
          cycle
        end if
        do a = 1, 4
          s%np_area(1, a, l) = s%block_weight(i, b)*(adj(i, 1)*s%block_grad(i, 1, a, b) + &
              adj(i, 2)*s%block_grad(i, 2, a, b) + adj(i, 3)*s%block_grad(i, 3, a, b))
          s%np_area(2, a, l) = s%block_weight(i, b)*(adj(i, 4)*s%block_grad(i, 1, a, b) + &
              adj(i, 5)*s%block_grad(i, 2, a, b) + adj(i, 6)*s%block_grad(i, 3, a, b))
          s%np_area(3, a, l) = s%block_weight(i, b)*(adj(i, 7)*s%block_grad(i, 1, a, b) + &
              adj(i, 8)*s%block_grad(i, 2, a, b) + adj(i, 9)*s%block_grad(i, 3, a, b))
        end do
      end do
    else
      if (rated) then
        call material_update_block(model%materials(s%material(l)), model%curves, n, f, det, &
                                   s%block_hist(:, :, b), tau, ok, rate, s%dt_step)
      else
        call material_update_block(model%materials(s%material(l)), model%curves, n, f, det, &
                                   s%block_hist(:, :, b), tau, ok)
      end if
      if (erodes) call erode_failed()
    end if
    if (face) then
      call block_face_internal_force(n, s%block_grad(:, :, :, b), s%block_weight(:, b), adj, &
                                     det, tau, force)
    else if (.not. averaged) then
      call block_internal_force(n, nn, s%block_grad(:, :, :, b), s%block_weight(:, b), adj, &
                                det, tau, force)
    end if
    ! the step bound: the quick one (no W0) for every cell, the exact one where the quick step
    ! is not above exact_step_below (a cell's choice depends on its own data only: the same
    ! bits on any number of ranks); every cell exact with hexahedra (their bound has more
    ! terms) and with mass scaling (each cell's bound places its added mass)
    quick = .not. (hexahedral .or. s%mass_scaling) .and. s%exact_step_below < huge(1.0_wp)
    if (quick) then
      call block_quick_omega_squared(n, s%block_weight(:, b), s%block_omega0(:, b), adj, det, &
                                     omega2)
      ! exact where omega^2 >= (2 TSSFAC / exact_step_below)^2 (or not a number)
      limit = (2.0_wp*model%controls%tssfac/s%exact_step_below)**2
      do i = 1, n
        exact(i) = merge(0.0_wp, 1.0_wp, omega2(i) < limit)
      end do
      if (any(exact(1:n) > 0.0_wp)) then
        s%exact_bound_blocks = s%exact_bound_blocks + 1
        call block_critical_omega_squared(n, s%block_weight(:, b), s%block_w0(:, :, b), adj, &
                                          det, s%lame(1, l), s%lame(2, l), omega_exact)
        do i = 1, n
          omega2(i) = merge(omega_exact(i), omega2(i), exact(i) > 0.0_wp)
        end do
      end if
    else
      s%exact_bound_blocks = s%exact_bound_blocks + 1
      call block_critical_omega_squared(n, s%block_weight(:, b), s%block_w0(:, :, b), adj, &
                                        det, s%lame(1, l), s%lame(2, l), omega2)
    end if
    if (hexahedral) then
      ! one-point hexahedra: the hourglass forces (velocities of the padded slots: the first
      ! node's, their gamma is zero) and the step: the larger of the element bound's and
      ! LS-DYNA's characteristic length rule's (the bound's alone for an element without a
      ! node inside the body, hex_rule), plus the hourglass stiffness' bound over the 8
      ! elements that share a node of a regular mesh, (K : C^-1) lambda_max(G)/8, C^-1 =
      ! adj adj^T / J^2 (doc/theory.md 2.8)
      hb = s%block_hex(b)
      do a = 1, 8                               ! the corners' current positions
        do i = 1, n
          k = s%hex_corner(i, a, hb)
          node = s%nodes(k, s%block_cell(first + i - 1))
          position(i, 1, a) = s%x0(1, node) + u(i, 1, k)
          position(i, 2, a) = s%x0(2, node) + u(i, 2, k)
          position(i, 3, a) = s%x0(3, node) + u(i, 3, k)
        end do
      end do
      do k = 1, 6
        do i = 1, n
          stiffness(i, k) = s%hex_stiffness(i, k, hb)
        end do
      end do
      do i = 1, n
        viscosity(i) = s%hex_viscosity(i, hb)
      end do
      if (erodes) then                        ! no hourglass force on a failed cell
        do i = 1, n
          if (.not. failed(i)) cycle
          stiffness(i, :) = 0.0_wp
          viscosity(i) = 0.0_wp
        end do
      end if
      call block_hourglass_forces(n, nn, u, viscous, v, s%block_grad(:, :, :, b), &
                                  s%hex_h(:, :, :, hb), s%hex_hx(:, :, :, hb), stiffness, &
                                  viscosity, adj, det, force, energy, power)
      l = s%block_cell(first)
      call block_hexahedron_frequency(n, position, s%block_weight(:, b), det, &
          s%lame(1, l) + 2.0_wp*s%lame(2, l), model%materials(s%material(l))%density, rule)
      do i = 1, n
        if (s%hex_rule(i, hb)) omega2(i) = min(omega2(i), rule(i))
      end do
      do i = 1, n
        s%hourglass_stored = s%hourglass_stored + energy(i)
        s%hourglass_power = s%hourglass_power + power(i)
        if (.not. det(i) > 0.0_wp) cycle
        do k = 1, 3               ! (adj adj^T), upper triangle, then divided by J^2
          c_inverse(k) = adj(i, k)**2 + adj(i, k + 3)**2 + adj(i, k + 6)**2
        end do
        c_inverse(4) = adj(i, 1)*adj(i, 2) + adj(i, 4)*adj(i, 5) + adj(i, 7)*adj(i, 8)
        c_inverse(5) = adj(i, 2)*adj(i, 3) + adj(i, 5)*adj(i, 6) + adj(i, 8)*adj(i, 9)
        c_inverse(6) = adj(i, 1)*adj(i, 3) + adj(i, 4)*adj(i, 6) + adj(i, 7)*adj(i, 9)
        omega2(i) = omega2(i) + s%hex_metric(i, hb)* &
            (sum(stiffness(i, 1:3)*c_inverse(1:3)) + &
             2.0_wp*sum(stiffness(i, 4:6)*c_inverse(4:6)))/(8.0_wp*det(i)**2)
      end do
    end if
    ! a failed cell bounds no step (left out below; a finite bound here keeps the block's
    ! steps at once)
    if (erodes) where (failed(1:n)) omega2(1:n) = 0.0_wp
    ! the cells' steps as take_cell_step computes them, for the whole block at once when no
    ! mass is added and every bound is a finite number (else cell by cell, which reports)
    steps_at_once = .not. s%mass_scaling
    if (steps_at_once) then
      do i = 1, n
        finite(i) = omega2(i) >= 0.0_wp .and. omega2(i) < huge(1.0_wp)
        dt_block(i) = 2.0_wp/sqrt(max(omega2(i), tiny(1.0_wp)))
        dt_block(i) = model%controls%tssfac*dt_block(i)
      end do
      steps_at_once = all(finite(1:n))
    end if
    ! the forces: added to the pushed nodes at once (the blocks run in ascending cell order
    ! for them: plan_pushed_assembly), kept for the halo's assembly otherwise (ELFORM 13: in
    ! nodal_pressure_forces); the step
    do i = 1, n
      l = s%block_cell(first + i - 1)
      if (.not. ok(i)) then
        call cell_forces(model, s, l)                ! reports the failure
        do a = 1, s%nnodes(l)
          force(i, :, a) = s%cell_force(:, a, l)
        end do
      end if
      if (averaged) then
        continue
      else if (store_all) then
        do a = 1, s%nnodes(l)
          s%cell_force(1, a, l) = force(i, 1, a)
          s%cell_force(2, a, l) = force(i, 2, a)
          s%cell_force(3, a, l) = force(i, 3, a)
        end do
      else
        do a = 1, s%nnodes(l)
          node = s%push_node(a, l)
          if (node > 0) then
            s%f_int_new(1, node) = s%f_int_new(1, node) + force(i, 1, a)
            s%f_int_new(2, node) = s%f_int_new(2, node) + force(i, 2, a)
            s%f_int_new(3, node) = s%f_int_new(3, node) + force(i, 3, a)
          else
            s%cell_force(1, a, l) = force(i, 1, a)
            s%cell_force(2, a, l) = force(i, 2, a)
            s%cell_force(3, a, l) = force(i, 3, a)
          end if
        end do
      end if
      if (.not. ok(i)) cycle
      if (failed(i)) then                    ! a failed cell bounds no step, adds no mass
        if (s%mass_scaling) s%added(1, 1:s%nnodes(l), l) = 0.0_wp
        cycle
      end if
      if (.not. steps_at_once) then
        call take_cell_step(model, s, l, omega2(i))
      else if (dt_block(i) <= s%dt_stable) then
        call keep_smallest_step(model, s, l, dt_block(i))
      end if
    end do

  contains

    !> After the material update: a failed cell gets its history back and no stress; a cell
    !> whose equivalent plastic strain reached the failure strain fails now (HIST_ALPHA
    !> negated: the mark; no stress from this cycle on).
    subroutine erode_failed()
      real(wp) :: j_stress
      associate (mat => model%materials(s%material(s%block_cell(first))))
        ! a block without failed cells, of a material that fails by plastic strain alone,
        ! whose cells all stay below it (the usual case, e.g. FAIL = 1e21): nothing to do
        if (.not. (mat%jc_fails .or. mat%add_erosion .or. any(failed(1:n)))) then
          if (all(s%block_hist(1:n, HIST_ALPHA, b) < mat%failure_strain)) return
        end if
        do i = 1, n
          if (failed(i)) then
            s%block_hist(i, :, b) = kept(i, :)
          else if (ok(i)) then
            j_stress = det(i)
            if (averaged) j_stress = jbar(i)
            if (.not. point_fails(mat, s%block_hist(i, HIST_ALPHA, b), &
                                  s%block_hist(i, HIST_DAMAGE, b), f(i, :), tau(i, :), &
                                  j_stress, s%time)) cycle
            s%block_hist(i, HIST_ALPHA, b) = -max(s%block_hist(i, HIST_ALPHA, b), &
                                                  tiny(1.0_wp))
            failed(i) = .true.
          else
            cycle
          end if
          tau(i, :) = 0.0_wp
        end do
      end associate
    end subroutine erode_failed

  end subroutine block_forces

  !> Nodal-pressure tetrahedra (ELFORM 13), first of the cycle's two nodal sums: every
  !> ELFORM 13 cell's current volume J V0 shared equally among its 4 nodes, summed at the
  !> nodes (the force assembly's order: the same bits on any number of ranks), divided by the
  !> nodes' reference volumes: the nodal J that element_mean_j averages (doc/theory.md 2.7).
  !> Collective (every rank calls it when the model has ELFORM 13 cells).
  subroutine nodal_volumes(s, halo)
    type(explicit_state_t), intent(inout) :: s        !< local state
    type(halo_t), intent(inout) :: halo               !< the force assembly's halo
    real(wp) :: x(3, 4), quarters(size(s%np_cells))
    integer :: k, l, a
    do k = 1, size(s%np_cells)
      l = s%np_cells(k)
      if (s%erosion) then
        if (cell_failed(s, l)) then          ! an eroded cell is left out of the means
          quarters(k) = 0.0_wp
          cycle
        end if
      end if
      do a = 1, 4
        x(:, a) = s%x0(:, s%nodes(a, l)) + s%u(:, s%nodes(a, l))
      end do
      do a = 2, 4
        x(:, a) = x(:, a) - x(:, 1)
      end do
      ! a quarter of the current volume, (x2 - x1) . ((x3 - x1) x (x4 - x1))/6 (= J V0)
      quarters(k) = (x(1, 2)*(x(2, 3)*x(3, 4) - x(3, 3)*x(2, 4)) + &
                     x(2, 2)*(x(3, 3)*x(1, 4) - x(1, 3)*x(3, 4)) + &
                     x(3, 2)*(x(1, 3)*x(2, 4) - x(2, 3)*x(1, 4)))/24.0_wp
    end do
    call nodal_mean(s, halo, quarters, 1.0_wp, s%np_node_j)
  end subroutine nodal_volumes

  !> Nodal-pressure tetrahedra, second sum, after the material updates: the nodes' pressure
  !> (the volume-weighted mean of their ELFORM 13 elements' Cauchy pressures), the element's
  !> force pressure the mean of its nodes' (its own at a node where materials meet), and the
  !> ELFORM 13 cells' forces, (dev(tau_bar)/J + p 1) V0 adj(F)^T g_a: the exact derivative of
  !> the strain energy of Fbar (doc/theory.md 2.7). They are added to the pushed columns in
  !> ascending cell order (after all blocks: plan_pushed_assembly) or kept. Collective.
  subroutine nodal_pressure_forces(s, halo)
    type(explicit_state_t), intent(inout) :: s        !< local state
    type(halo_t), intent(inout) :: halo               !< the force assembly's halo
    real(wp) :: p, sigma(6), force(3), shares(size(s%np_cells))
    integer :: k, l, a, node, column
    do k = 1, size(s%np_cells)
      l = s%np_cells(k)
      shares(k) = 0.25_wp*s%weight(l)*s%np_pressure(l)     ! (0 on an eroded cell)
    end do
    call nodal_mean(s, halo, shares, 0.0_wp, s%np_node_p)
    do k = 1, size(s%np_cells)                        ! ascending cell order (pushed columns)
      l = s%np_cells(k)
      p = 0.0_wp
      do a = 1, 4
        node = s%nodes(a, l)
        if (s%np_mixed(node)) then
          p = p + s%np_pressure(l)
        else
          p = p + s%np_node_p(node)
        end if
      end do
      p = 0.25_wp*p
      s%np_force_pressure(l) = p
      ! Cauchy stress dev(tau_bar)/J + p 1 on the area vectors
      sigma = s%np_deviator(:, l)
      sigma(1:3) = sigma(1:3) + p
      do a = 1, 4
        force(1) = sigma(1)*s%np_area(1, a, l) + sigma(4)*s%np_area(2, a, l) + &
                   sigma(6)*s%np_area(3, a, l)
        force(2) = sigma(4)*s%np_area(1, a, l) + sigma(2)*s%np_area(2, a, l) + &
                   sigma(5)*s%np_area(3, a, l)
        force(3) = sigma(6)*s%np_area(1, a, l) + sigma(5)*s%np_area(2, a, l) + &
                   sigma(3)*s%np_area(3, a, l)
        column = s%push_node(a, l)
        if (column > 0) then
          s%f_int_new(:, column) = s%f_int_new(:, column) + force
        else
          s%cell_force(:, a, l) = force
        end if
      end do
    end do
  end subroutine nodal_pressure_forces

  !> A nodal mean over the ELFORM 13 elements: each element's share (its value times V0/4) added
  !> at its 4 nodes in ascending cell order (the assembly plan's: the same bits on any number
  !> of ranks), the sums over the chunks and ranks, divided by the nodes' reference volumes;
  !> nodes without ELFORM 13 elements get the default.
  subroutine nodal_mean(s, halo, shares, default, nodal)
    type(explicit_state_t), intent(inout) :: s        !< local state
    type(halo_t), intent(inout) :: halo               !< the force assembly's halo
    real(wp), intent(in) :: shares(:)                 !< (ELFORM 13 cells) share per corner
    real(wp), intent(in) :: default                   !< value at nodes without any
    real(wp), intent(out) :: nodal(:)                 !< (nnode) the nodal means
    integer :: k, a
    call set_to_zero(size(s%np_sums), s%np_sums)
    do k = 1, size(s%np_cells)
      do a = 1, 4
        s%np_sums(1, s%np_column(a, k)) = s%np_sums(1, s%np_column(a, k)) + shares(k)
      end do
    end do
    call halo_assemble_summed(halo, s%np_sums)
    do k = 1, s%nnode
      nodal(k) = default
      if (s%np_volume0(k) > 0.0_wp) nodal(k) = s%np_sums(1, k)/s%np_volume0(k)
    end do
  end subroutine nodal_mean

  !> Jbar of ELFORM 13 cell l: the mean of its 4 nodes' J (the cell's own J, det, at a node
  !> where ELFORM 13 elements of different materials meet).
  real(wp) function element_mean_j(s, l, det)
    type(explicit_state_t), intent(in) :: s           !< local state
    integer, intent(in) :: l                          !< local ELFORM 13 cell
    real(wp), intent(in) :: det                       !< its J = det F
    integer :: a, node
    element_mean_j = 0.0_wp
    do a = 1, 4
      node = s%nodes(a, l)
      if (s%np_mixed(node)) then
        element_mean_j = element_mean_j + det
      else
        element_mean_j = element_mean_j + s%np_node_j(node)
      end if
    end do
    element_mean_j = 0.25_wp*element_mean_j
  end function element_mean_j

  !> (Jbar/J)^(1/3), the factor of Fbar = (Jbar/J)^(1/3) F; 1 where J or Jbar is not positive
  !> (the material update then fails on F itself and reports it).
  elemental real(wp) function volume_scale(jbar, det)
    real(wp), intent(in) :: jbar                      !< mean nodal J of the element
    real(wp), intent(in) :: det                       !< the element's J
    volume_scale = 1.0_wp
    if (det > 0.0_wp .and. jbar > 0.0_wp) volume_scale = inverse_cube_root(det/jbar)
  end function volume_scale

  !> Take the pressure out of a Kirchhoff stress at Fbar: the Cauchy pressure tr(tau)/(3 Jbar)
  !> into pressure, the diagonal left deviatoric.
  pure subroutine split_pressure(t11, t22, t33, jbar, pressure)
    real(wp), intent(inout) :: t11, t22, t33          !< diagonal of tau (made deviatoric)
    real(wp), intent(in) :: jbar                      !< J of Fbar
    real(wp), intent(out) :: pressure                 !< Cauchy pressure (tension positive)
    real(wp) :: mean
    mean = (t11 + t22 + t33)/3.0_wp
    pressure = mean/jbar
    t11 = t11 - mean
    t22 = t22 - mean
    t33 = t33 - mean
  end subroutine split_pressure

  !> Keep the area vectors V0 adj(F)^T g_a of ELFORM 13 cell l (a = 1..4): its nodal forces
  !> per unit Cauchy pressure, which nodal_pressure_forces multiplies by the averaged one.
  pure subroutine keep_area_vectors(s, l, grad, adj)
    type(explicit_state_t), intent(inout) :: s        !< local state
    integer, intent(in) :: l                          !< local ELFORM 13 cell
    real(wp), intent(in) :: grad(3, 4)                !< its reference gradients
    real(wp), intent(in) :: adj(9)                    !< adj(F), column by column
    integer :: a
    do a = 1, 4       ! (adj^T g)_r = sum_k adj(k, r) g_k
      s%np_area(1, a, l) = s%weight(l)*(adj(1)*grad(1, a) + adj(2)*grad(2, a) + adj(3)*grad(3, a))
      s%np_area(2, a, l) = s%weight(l)*(adj(4)*grad(1, a) + adj(5)*grad(2, a) + adj(6)*grad(3, a))
      s%np_area(3, a, l) = s%weight(l)*(adj(7)*grad(1, a) + adj(8)*grad(2, a) + adj(9)*grad(3, a))
    end do
  end subroutine keep_area_vectors

  !> One-point hexahedra: the local copies of their hourglass data (cells' hexahedron
  !> arrays; every rank learns whether the model has any, which turns off work stealing), the
  !> shape vectors' parts in the blocks' layout: each node's base vectors h_aI (those of a
  !> repeated corner added together) and hX_a = sum_I h_aI X_I, from which the kernel forms
  !> gamma_aI = h_aI - hX_a . B_I (doc/theory.md 2.8).
  subroutine hourglass_set_up(s, cells)
    type(explicit_state_t), intent(inout) :: s        !< local state (blocks built)
    type(cells_t), intent(in) :: cells                !< all cells
    integer :: l, h, b, hb, k, i, a, slot, nhb
    s%hourglass = cells%n_hex > 0
    if (.not. s%hourglass) return
    allocate(s%block_hex(s%nblock))
    nhb = 0
    do b = 1, s%nblock          ! (a block holds cells of one kind: hexahedral or not)
      s%block_hex(b) = 0
      if (s%block_start(b + 1) == s%block_start(b)) cycle
      if (cells%hex_of(s%cell_global(s%block_cell(s%block_start(b)))) == 0) cycle
      nhb = nhb + 1
      s%block_hex(b) = nhb
    end do
    allocate(s%hex_h(BLOCK_CELLS, CELL_MAX_NODES, HOURGLASS_MODES, nhb), &
             s%hex_hx(BLOCK_CELLS, 3, HOURGLASS_MODES, nhb), s%hex_corner(BLOCK_CELLS, 8, nhb), &
             s%hex_stiffness(BLOCK_CELLS, 6, nhb), s%hex_viscosity(BLOCK_CELLS, nhb), &
             s%hex_metric(BLOCK_CELLS, nhb), s%hex_rule(BLOCK_CELLS, nhb), s%hex_viscous(nhb))
    s%hex_h = 0_i1
    s%hex_hx = 0.0_wp
    s%hex_corner = 1_i1
    s%hex_stiffness = 0.0_wp
    s%hex_viscosity = 0.0_wp
    s%hex_metric = 0.0_wp
    s%hex_rule = .true.                  ! (explicit_dynamics' set-up decides)
    do b = 1, s%nblock
      hb = s%block_hex(b)
      if (hb == 0) cycle
      do k = s%block_start(b), s%block_start(b + 1) - 1
        l = s%block_cell(k)
        i = k - s%block_start(b) + 1
        h = cells%hex_of(s%cell_global(l))
        s%hex_stiffness(i, :, hb) = cells%hg_stiffness(:, h)
        s%hex_viscosity(i, hb) = cells%hg_viscosity(h)
        s%hex_metric(i, hb) = cells%hg_metric(h)
        do a = 1, 8
          slot = cells%hg_corner(a, h)
          s%hex_corner(i, a, hb) = int(slot, i1)
          s%hex_h(i, slot, :, hb) = s%hex_h(i, slot, :, hb) + HOURGLASS_VECTORS(a, :)
          s%hex_hx(i, :, :, hb) = s%hex_hx(i, :, :, hb) + &
              spread(s%x0(:, s%nodes(slot, l)), 2, HOURGLASS_MODES)* &
              spread(real(HOURGLASS_VECTORS(a, :), wp), 1, 3)
        end do
      end do
      s%hex_viscous(hb) = any(s%hex_viscosity(:, hb) > 0.0_wp)
    end do
  end subroutine hourglass_set_up

  !> Set-up of the nodal-pressure tetrahedra (3D, after the blocks; collective when the model
  !> has ELFORM 13 cells): which local cells are, the nodes' reference volumes and where ELFORM
  !> 13 elements of different materials meet (the counts, sums and sums of squares of the
  !> material indices at the nodes: equal materials iff count sum(m^2) = sum(m)^2).
  subroutine nodal_pressure_set_up(s, cells, halo)
    type(explicit_state_t), intent(inout) :: s        !< local state (blocks built)
    type(cells_t), intent(in) :: cells                !< all cells
    type(halo_t), intent(inout) :: halo               !< the force assembly's halo
    real(wp), allocatable :: values(:,:,:), sums(:,:)
    real(wp) :: m
    integer :: k, l, a
    s%nodal_pressure = any(cells%nodal_pressure)
    if (.not. s%nodal_pressure) return
    s%np_cell = cells%nodal_pressure(s%cell_global)
    s%np_cells = pack([(l, l = 1, s%ncell)], s%np_cell)
    allocate(s%np_sums(1, halo%ntarget), s%np_column(4, size(s%np_cells)))
    allocate(values(3, CELL_MAX_NODES, s%ncell), sums(3, halo%ntarget))
    values = 0.0_wp
    do k = 1, size(s%np_cells)
      l = s%np_cells(k)
      m = real(s%material(l), wp)
      do a = 1, 4
        s%np_column(a, k) = halo%source_target(a + halo%slots*(l - 1))
        values(:, a, l) = [1.0_wp, m, m*m]
      end do
    end do
    call nodal_reference_volumes(s, halo)
    call halo_assemble(halo, values, sums)
    s%np_mixed = sums(1, 1:s%nnode)*sums(3, 1:s%nnode) /= sums(2, 1:s%nnode)**2
    allocate(s%np_node_j(s%nnode), s%np_node_p(s%nnode), s%np_jbar(s%ncell), &
             s%np_pressure(s%ncell), s%np_force_pressure(s%ncell), s%np_area(3, 4, s%ncell), &
             s%np_deviator(6, s%ncell))
    s%np_area = 0.0_wp
    s%np_deviator = 0.0_wp
    s%np_node_j = 1.0_wp
    s%np_node_p = 0.0_wp
    s%np_jbar = 1.0_wp
    s%np_pressure = 0.0_wp
    s%np_force_pressure = 0.0_wp
  end subroutine nodal_pressure_set_up

  !> Nodal-pressure tetrahedra: the nodes' reference volumes np_volume0, the sums of V0/4 of
  !> their ELFORM 13 cells that have not eroded (in the nodal means' order). Collective.
  subroutine nodal_reference_volumes(s, halo)
    type(explicit_state_t), intent(inout) :: s        !< local state (np_column set)
    type(halo_t), intent(inout) :: halo               !< the force assembly's halo
    integer :: k, l, a
    call set_to_zero(size(s%np_sums), s%np_sums)
    do k = 1, size(s%np_cells)
      l = s%np_cells(k)
      if (s%erosion) then
        if (cell_failed(s, l)) cycle
      end if
      do a = 1, 4
        s%np_sums(1, s%np_column(a, k)) = s%np_sums(1, s%np_column(a, k)) + 0.25_wp*s%weight(l)
      end do
    end do
    call halo_assemble_summed(halo, s%np_sums)
    s%np_volume0 = s%np_sums(1, 1:s%nnode)
  end subroutine nodal_reference_volumes

  !> Local cell l has failed (erosion: its HIST_ALPHA negated).
  logical function cell_failed(s, l)
    type(explicit_state_t), intent(in) :: s           !< local state
    integer, intent(in) :: l                          !< local cell
    if (s%nblock > 0) then
      cell_failed = s%block_hist(s%cell_slot(l), HIST_ALPHA, s%cell_block(l)) < 0.0_wp
    else
      cell_failed = s%hist(HIST_ALPHA, l) < 0.0_wp
    end if
  end function cell_failed

  !> Pushed assembly of the 3D cell loop: block_forces adds a cell's contribution straight
  !> into its column of f_int_new (the layout's target: its node's, or its node's partial sum
  !> of the cell's chunk) when the blocks reach that column's cells in ascending global cell
  !> order (the order of the layout's plan, so the sums have the same bits on any number of
  !> ranks). That pushes every column except where materials or cell kinds change (the blocks
  !> group cells by those); those columns are summed by the halo from the cell array.
  subroutine plan_pushed_assembly(s, halo)
    type(explicit_state_t), intent(inout) :: s        !< local state (blocks built)
    type(halo_t), intent(inout) :: halo               !< force exchange: told the pushed columns
    integer, allocatable :: position(:), last_position(:)
    logical, allocatable :: pushed(:)
    integer :: m, l, a, column
    ! the order in which contributions reach the nodal array: the blocks' cells
    allocate(position(s%ncell), last_position(halo%ntarget), pushed(halo%ntarget))
    ! (the order in which each cell's contributions are added: its place in the blocks, or
    ! for an ELFORM 13 cell after all blocks, in nodal_pressure_forces)
    do m = 1, s%ncell
      position(s%block_cell(m)) = m
    end do
    ! ELFORM 13 cells add their forces after all blocks, in ascending order
    if (s%nodal_pressure) then
      do m = 1, size(s%np_cells)
        position(s%np_cells(m)) = s%ncell + m
      end do
    end if
    pushed = .true.
    last_position = 0
    do l = 1, s%ncell                                 ! ascending local = global cell order
      do a = 1, s%nnodes(l)
        column = halo%source_target(a + halo%slots*(l - 1))
        if (position(l) < last_position(column)) pushed(column) = .false.
        last_position(column) = position(l)
      end do
    end do
    call halo_assembly_push_nodes(halo, pushed)
    allocate(s%push_node(CELL_MAX_NODES, s%ncell))
    s%push_node = 0
    do l = 1, s%ncell
      do a = 1, s%nnodes(l)
        column = halo%source_target(a + halo%slots*(l - 1))
        if (pushed(column)) s%push_node(a, l) = column
      end do
    end do
  end subroutine plan_pushed_assembly

  !> Stiffness-weighted mass split of the local cells at the current displacements
  !> (doc/theory.md 7): every cell's weights (cell_split_weights), their sums at the nodes
  !> over all cells (the halo's assembly, in the same order whatever the number of ranks, so
  !> the same bits), each cell's mass shares m_node k_a / sum k, with m_node the lumped mass
  !> without mass scaling; then (without mass scaling) SPLIT_PASSES rebalancing passes, each
  !> moving the nodes' mass towards the cells whose bound omega_c^2 is highest (new weights
  !> share x omega_c^2, a failed cell's 0: it has no stiffness); last each cell's inverse-mass
  !> metric, which the step bound reads from then on (with mass scaling, the shares that
  !> carry the added mass too). Called at set-up and every MASS_SPLIT_INTERVAL cycles by the driver: any split is
  !> a valid one, so between the calls the bound stays safe and only less sharp.
  subroutine explicit_mass_split(s, halo)
    type(explicit_state_t), intent(inout) :: s        !< local state (blocks built)
    type(halo_t), intent(inout) :: halo               !< the halo of the force assembly
    real(wp), allocatable :: weights(:,:,:), sums(:,:), f(:,:,:)
    real(wp) :: grad(3, CELL_MAX_NODES), w0(3, 3), ue(3, CELL_MAX_NODES)
    real(wp) :: share(CELL_MAX_NODES)
    integer :: dim, l, nn, k, pass
    dim = s%dim
    allocate(weights(1, CELL_MAX_NODES, s%ncell), sums(1, halo%ntarget), f(3, 3, s%ncell))
    weights = 0.0_wp
    do l = 1, s%ncell
      nn = s%nnodes(l)
      call local_cell_gradients(l)
      do k = 1, nn
        ue(1:dim, k) = s%u(1:dim, s%nodes(k, l))
      end do
      call cell_deformation_gradient(dim, nn, grad(1:dim, :), ue(1:dim, 1:nn), f(:, :, l))
      call cell_split_weights(dim, nn, s%weight(l), grad, f(:, :, l), weights(1, :, l))
    end do
    call halo_assemble(halo, weights, sums)
    do pass = 1, merge(0, SPLIT_PASSES, s%mass_scaling)
      do l = 1, s%ncell
        nn = s%nnodes(l)
        call local_cell_gradients(l)
        call cell_shares(l)
        if (s%erosion) then
          if (cell_failed(s, l)) then
            weights(1, 1:nn, l) = 0.0_wp
            cycle
          end if
        end if
        call cell_rebalance_weights(dim, nn, s%weight(l), grad, share, f(:, :, l), &
                                    s%lame(1, l), s%lame(2, l), weights(1, :, l))
      end do
      call halo_assemble(halo, weights, sums)
    end do
    do l = 1, s%ncell
      nn = s%nnodes(l)
      call local_cell_gradients(l)
      call cell_shares(l)
      call inverse_mass_metric(dim, nn, grad, share, w0)
      if (s%nblock > 0) then
        call set_cell_metric(s, l, w0)
      else
        s%w0(:, :, l) = w0(1:dim, 1:dim)
      end if
      if (s%mass_scaling) s%share(1:nn, l) = share(1:nn)
    end do
    s%new_split = .true.

  contains

    !> grad: the reference gradients of local cell l (blocks in 3D, per-cell array in 2D).
    subroutine local_cell_gradients(l)
      integer, intent(in) :: l                        !< local cell
      if (s%nblock > 0) then
        call block_cell_gradients(s, l, grad)
      else
        grad = 0.0_wp
        grad(1:dim, :) = s%grad(:, :, l)
      end if
    end subroutine local_cell_gradients

    !> share: local cell l's mass shares of its nodes' physical masses by the weights.
    subroutine cell_shares(l)
      integer, intent(in) :: l                        !< local cell
      integer :: node
      share = 0.0_wp
      do k = 1, s%nnodes(l)
        node = s%nodes(k, l)
        if (sums(1, node) > 0.0_wp) share(k) = s%physical_mass(node)*weights(1, k, l)/ &
                                               sums(1, node)
      end do
    end subroutine cell_shares

  end subroutine explicit_mass_split

  !> The model element a local cell belongs to (the first of its one or two elements).
  integer function first_element(s, l)
    type(explicit_state_t), intent(in) :: s     !< local state
    integer, intent(in) :: l                    !< local cell
    first_element = s%cell_element(l)
  end function first_element

end module mefem_explicit_cell_forces
