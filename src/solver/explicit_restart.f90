!> Restart of the explicit analysis (*DATABASE_BINARY_D3DUMP, *DATABASE_BINARY_RUNRSF, d3kil
!> sw1 and sw3, a stopping signal; `mefem r=d3dump01`): the state at the end of a cycle, in
!> global order, so that a run continued from it on any number of ranks computes the same bits
!> as the run that was never stopped.
!>
!> What a cycle carries to the next (explicit_dynamics): the time, the cycle, the step taken
!> and the step to take; at the nodes u^n, v^{n-1/2}, a^n, the forces f_int, f_ext and f_con at
!> t^n, the masses (with the mass scaling's added mass) and the prescribed dofs' driven flags;
!> at the cells the material history and the step bound's mass split (W0 and the shares,
!> refreshed every MASS_SPLIT_INTERVAL cycles); the rigid bodies' motion and resultants, the
!> moving walls' shift, the tiebreaks' held nodes, the contacts' state (mortar_contact's
!> records: candidates, last pairs, normals, tractions), the erosion's failed cells, the energy
!> sums, the output schedule. Energy sums are kept per rank and summed when written: the file
!> holds their sum, which rank 0 takes on restart (glstat's energies may then differ from the
!> uninterrupted run's in the last bits of the sum's order; nodal results do not).
!>
!> Nodal and cell arrays are gathered on rank 0 (owned nodes, the cells each rank computes)
!> and every rank reads them whole and keeps its own: memory O(model) during the read and
!> write, as the replicated model needs anyway.
module mefem_explicit_restart
  use mefem_kinds, only: wp
  use mefem_comm, only: comm_sum, comm_gatherv_int, comm_gatherv_real, comm_is_root
  use mefem_errors, only: fatal
  use mefem_strings, only: itoa
  use mefem_model, only: model_t
  use mefem_cells, only: cells_t, CELL_MAX_NODES
  use mefem_material_state, only: NHIST
  use mefem_explicit_layout, only: explicit_layout_t
  use mefem_halo, only: halo_t
  use mefem_mortar_contact, only: mortar_contact_erode, mortar_contact_restart_put, &
                                  mortar_contact_restart_get
  use mefem_explicit_state, only: explicit_state_t
  use mefem_explicit_cell_forces, only: nodal_reference_volumes, set_cell_metric
  use mefem_stable_time_step, only: metric_unpacked
  use mefem_explicit_output, only: schedule_t
  use mefem_restart_file, only: restart_file_t, restart_put_reals, restart_put_ints, &
                                restart_put_text, restart_get_reals, restart_get_ints, &
                                restart_get_text, restart_checksum
  use mefem_results, only: results_restart_header_put, results_restart_header_skip, &
                           results_restart_put, results_restart_get
  implicit none
  private

  public :: explicit_restart_put, explicit_restart_get

  !> Where the run stands at the end of a cycle (explicit_dynamics' loop variables).
  type, public :: run_point_t
    integer :: cycle = 0                       !< cycles done
    real(wp) :: t = 0.0_wp                     !< time reached
    real(wp) :: dt = 0.0_wp                    !< the step the next cycle takes
    real(wp) :: dt_old = 0.0_wp                !< the step the last cycle took
    real(wp) :: dt_first = 0.0_wp              !< the first step (DTMIN's reference)
    integer :: dumps = 0                       !< d3dump files written so far
  end type run_point_t

  integer, parameter :: N_ENERGIES = 9         !< energy sums in the file
  integer, parameter :: BODY_REALS = 44        !< reals per rigid body

contains

  !> Write the state at the end of a cycle into an open restart file (collective: every rank
  !> calls it, rank 0 writes).
  subroutine explicit_restart_put(f, model, cells, layout, s, point, schedule)
    type(restart_file_t), intent(inout) :: f          !< file being written
    type(model_t), intent(in) :: model                !< resolved model
    type(cells_t), intent(in) :: cells                !< all cells
    type(explicit_layout_t), intent(in) :: layout     !< this rank's share
    type(explicit_state_t), intent(in) :: s           !< local state
    type(run_point_t), intent(in) :: point            !< where the run stands
    type(schedule_t), intent(in) :: schedule          !< output schedule
    real(wp) :: energies(N_ENERGIES)
    real(wp), allocatable :: local(:,:)
    integer :: l, k, d
    d = s%dim
    call results_restart_header_put(f)
    call restart_put_text(f, 'analysis', 'explicit')
    call restart_put_ints(f, 'model.sizes', 6, model_sizes(model, cells, layout, s))
    call restart_put_reals(f, 'model.coordinates', 1, &
                           [restart_checksum(model%nodes%x(:, 1:model%nodes%n))])
    call restart_put_ints(f, 'run.cycle', 2, [point%cycle, point%dumps])
    call restart_put_reals(f, 'run.times', 4, [point%t, point%dt, point%dt_old, point%dt_first])
    call restart_put_reals(f, 'schedule.times', 10, [schedule%next_plot, schedule%next_glstat, &
        schedule%next_nodout, schedule%next_rcforc, schedule%last_plot, schedule%last_glstat, &
        schedule%last_nodout, schedule%last_rcforc, schedule%initial_energy, schedule%next_dump])
    call restart_put_ints(f, 'schedule.counters', 2, [schedule%plot_state, &
        merge(1, 0, schedule%have_initial_energy)])
    energies = [s%internal_energy, s%contact_energy, s%external_work, s%wall_work, &
                s%hourglass_dissipated, s%eroded_energy, s%hourglass_stored, &
                s%hourglass_power, 0.0_wp]
    call comm_sum(energies)
    energies(9) = s%body_load_work                    ! (replicated)
    call restart_put_reals(f, 'energies', N_ENERGIES, energies)
    ! nodes
    call put_nodal(f, 'nodes.u', s, layout, d, s%u)
    call put_nodal(f, 'nodes.v', s, layout, d, s%v)
    call put_nodal(f, 'nodes.a', s, layout, d, s%a)
    call put_nodal(f, 'nodes.f_int', s, layout, d, s%f_int(:, 1:s%nnode))
    call put_nodal(f, 'nodes.f_ext', s, layout, d, s%f_ext)
    call put_nodal(f, 'nodes.f_con', s, layout, d, s%f_con)
    call put_nodal(f, 'nodes.mass', s, layout, 1, reshape(s%mass, [1, s%nnode]))
    call put_nodal(f, 'nodes.driven', s, layout, d, merge(1.0_wp, 0.0_wp, s%driven))
    ! cells
    allocate(local(NHIST, s%ncell))
    do l = 1, s%ncell
      if (s%nblock > 0) then
        local(:, l) = s%block_hist(s%cell_slot(l), :, s%cell_block(l))
      else
        local(:, l) = s%hist(:, l)
      end if
    end do
    call put_cells(f, 'cells.history', s, cells, NHIST, local)
    deallocate(local)
    allocate(local(d*d, s%ncell))
    do l = 1, s%ncell
      if (s%nblock > 0) then
        local(:, l) = reshape(metric_unpacked(s%block_w0(s%cell_slot(l), :, s%cell_block(l))), &
                              [d*d])
      else
        local(:, l) = reshape(s%w0(:, :, l), [d*d])
      end if
    end do
    call put_cells(f, 'cells.mass_metric', s, cells, d*d, local)
    if (s%mass_scaling) then
      call put_cells(f, 'cells.mass_shares', s, cells, CELL_MAX_NODES, s%share)
      call put_cells(f, 'cells.added_mass', s, cells, CELL_MAX_NODES, s%added(1, :, :))
    end if
    if (s%erosion) then
      call put_cells(f, 'cells.eroded', s, cells, 1, &
                     reshape(merge(1.0_wp, 0.0_wp, s%cell_counted), [1, s%ncell]))
      call restart_put_ints(f, 'cells.eroded_count', 1, [s%eroded_cells])
    end if
    ! rigid bodies, walls, ties (replicated)
    call restart_put_reals(f, 'bodies', BODY_REALS*s%bodies%n, &
                           [(body_record(k), k = 1, s%bodies%n)])
    if (s%bodies%n > 0) then
      call restart_put_reals(f, 'bodies.resultants', 9*s%bodies%n, &
                             [s%body_force, s%body_moment, s%body_load])
    end if
    if (s%nwall > 0) call restart_put_reals(f, 'walls.shift', 3*s%nwall, s%wall_shift)
    if (s%tied%n > 0) call restart_put_ints(f, 'ties.held', s%tied%n, &
                                            merge(1, 0, s%tied%held))
    ! contacts (replicated), then the outputs' continuation
    call mortar_contact_restart_put(s%contact, f)
    call results_restart_put(f)
  contains
    !> Rigid body k's motion as a flat record.
    function body_record(k) result(r)
      integer, intent(in) :: k                        !< body
      real(wp) :: r(BODY_REALS)
      associate (b => s%bodies%body(k))
        r = [b%centre, b%centre_old, reshape(b%rotation, [9]), reshape(b%rotation_old, [9]), &
             b%velocity, b%omega, b%angular_momentum, b%angle, b%reaction_force, &
             b%reaction_moment, b%reaction_work, b%dt_last]
      end associate
    end function body_record
  end subroutine explicit_restart_put

  !> Read the state written by explicit_restart_put into a state set up as for t = 0 (after
  !> set_up and open_histories), on any number of ranks (collective).
  subroutine explicit_restart_get(f, model, cells, layout, halo, s, point, schedule)
    type(restart_file_t), intent(inout) :: f          !< file being read
    type(model_t), intent(in) :: model                !< resolved model
    type(cells_t), intent(in) :: cells                !< all cells
    type(explicit_layout_t), intent(in) :: layout     !< this rank's share
    type(halo_t), intent(inout) :: halo               !< the force assembly's halo
    type(explicit_state_t), intent(inout) :: s        !< local state, set up for t = 0
    type(run_point_t), intent(out) :: point           !< where the run stood
    type(schedule_t), intent(inout) :: schedule       !< output schedule (intervals set)
    character(len=:), allocatable :: analysis
    real(wp) :: energies(N_ENERGIES), times(10), scalar(4)
    real(wp), allocatable :: local(:,:), body(:), resultants(:), eroded(:)
    integer :: sizes(6), counters(2), l, k, d, j, e, c, one(1)
    integer, allocatable :: held(:)
    d = s%dim
    call results_restart_header_skip(f)
    call restart_get_text(f, 'analysis', analysis)
    if (analysis /= 'explicit') call fatal('restart file "'//f%path//'" was written by the '// &
        analysis//' analysis; this deck runs the explicit analysis')
    call restart_get_ints(f, 'model.sizes', 6, sizes)
    if (any(sizes /= model_sizes(model, cells, layout, s))) call fatal('restart file "'// &
        f%path//'" was written for another model (nodes, elements, cells, contacts or '// &
        'rigid bodies differ): restart with the deck it was written with')
    call restart_get_reals(f, 'model.coordinates', 1, scalar(1:1))
    if (scalar(1) /= restart_checksum(model%nodes%x(:, 1:model%nodes%n))) call fatal( &
        'restart file "'//f%path//'" was written for a mesh with other coordinates: restart '// &
        'with the deck it was written with')
    call restart_get_ints(f, 'run.cycle', 2, counters)
    point%cycle = counters(1)
    point%dumps = counters(2)
    call restart_get_reals(f, 'run.times', 4, scalar)
    point%t = scalar(1)
    point%dt = scalar(2)
    point%dt_old = scalar(3)
    point%dt_first = scalar(4)
    call restart_get_reals(f, 'schedule.times', 10, times)
    schedule%next_plot = times(1)
    schedule%next_glstat = times(2)
    schedule%next_nodout = times(3)
    schedule%next_rcforc = times(4)
    schedule%last_plot = times(5)
    schedule%last_glstat = times(6)
    schedule%last_nodout = times(7)
    schedule%last_rcforc = times(8)
    schedule%initial_energy = times(9)
    schedule%next_dump = times(10)
    call restart_get_ints(f, 'schedule.counters', 2, counters)
    schedule%plot_state = counters(1)
    schedule%have_initial_energy = counters(2) == 1
    call restart_get_reals(f, 'energies', N_ENERGIES, energies)
    if (.not. comm_is_root()) energies(1:8) = 0.0_wp    ! rank 0 carries the sums
    s%internal_energy = energies(1)
    s%contact_energy = energies(2)
    s%external_work = energies(3)
    s%wall_work = energies(4)
    s%hourglass_dissipated = energies(5)
    s%eroded_energy = energies(6)
    s%hourglass_stored = energies(7)
    s%hourglass_power = energies(8)
    s%body_load_work = energies(9)
    ! nodes
    call get_nodal(f, 'nodes.u', s, layout, d, s%u)
    call get_nodal(f, 'nodes.v', s, layout, d, s%v)
    call get_nodal(f, 'nodes.a', s, layout, d, s%a)
    allocate(local(d, s%nnode))
    call get_nodal(f, 'nodes.f_int', s, layout, d, local)
    s%f_int(:, 1:s%nnode) = local
    call get_nodal(f, 'nodes.f_ext', s, layout, d, s%f_ext)
    call get_nodal(f, 'nodes.f_con', s, layout, d, s%f_con)
    deallocate(local)
    allocate(local(1, s%nnode))
    call get_nodal(f, 'nodes.mass', s, layout, 1, local)
    s%mass = local(1, :)
    deallocate(local)
    allocate(local(d, s%nnode))
    call get_nodal(f, 'nodes.driven', s, layout, d, local)
    s%driven = local > 0.5_wp
    deallocate(local)
    ! cells
    allocate(local(NHIST, s%ncell))
    call get_cells(f, 'cells.history', s, cells, NHIST, local)
    do l = 1, s%ncell
      if (s%nblock > 0) then
        s%block_hist(s%cell_slot(l), :, s%cell_block(l)) = local(:, l)
      else
        s%hist(:, l) = local(:, l)
      end if
    end do
    deallocate(local)
    allocate(local(d*d, s%ncell))
    call get_cells(f, 'cells.mass_metric', s, cells, d*d, local)
    do l = 1, s%ncell
      if (s%nblock > 0) then
        call set_cell_metric(s, l, reshape(local(:, l), [3, 3]))
      else
        s%w0(:, :, l) = reshape(local(:, l), [d, d])
      end if
    end do
    deallocate(local)
    if (s%mass_scaling) then
      call get_cells(f, 'cells.mass_shares', s, cells, CELL_MAX_NODES, s%share)
      allocate(local(CELL_MAX_NODES, s%ncell))
      call get_cells(f, 'cells.added_mass', s, cells, CELL_MAX_NODES, local)
      s%added(1, :, :) = local
      deallocate(local)
    end if
    if (s%erosion) then                       ! (every rank needs every cell's flag)
      allocate(eroded(cells%n))
      call restart_get_reals(f, 'cells.eroded', cells%n, eroded)
      s%cell_counted = eroded(s%cell_global(1:s%ncell)) > 0.5_wp
      call restart_get_ints(f, 'cells.eroded_count', 1, one)
      s%eroded_cells = one(1)
    end if
    ! rigid bodies, walls, ties
    allocate(body(BODY_REALS*s%bodies%n))
    call restart_get_reals(f, 'bodies', size(body), body)
    do k = 1, s%bodies%n
      call set_body(k, body(BODY_REALS*(k - 1) + 1:BODY_REALS*k))
    end do
    if (s%bodies%n > 0) then
      allocate(resultants(9*s%bodies%n))
      call restart_get_reals(f, 'bodies.resultants', size(resultants), resultants)
      s%body_force = reshape(resultants(1:3*s%bodies%n), [3, s%bodies%n])
      s%body_moment = reshape(resultants(3*s%bodies%n + 1:6*s%bodies%n), [3, s%bodies%n])
      s%body_load = reshape(resultants(6*s%bodies%n + 1:), [3, s%bodies%n])
    end if
    if (s%nwall > 0) call restart_get_reals(f, 'walls.shift', 3*s%nwall, s%wall_shift)
    if (s%tied%n > 0) then
      allocate(held(s%tied%n))
      call restart_get_ints(f, 'ties.held', s%tied%n, held)
      do k = 1, s%tied%n                         ! released ties: as tie_accelerations does
        s%tied%held(k) = held(k) == 1
        if (s%tied%held(k)) cycle
        l = s%tie_slave_local(k)
        if (l <= 0) cycle
        s%tied_node(l) = .false.
        s%fixed(:, l) = s%tie_fixed(1:d, k)
      end do
    end if
    ! eroded elements: the counts of live cells, the contacts' and the nodal volumes' view
    ! of them, as erosion_update left them (before the contacts' own records are read)
    if (s%erosion) then
      if (s%eroded_cells > 0) then
        do c = 1, cells%n
          if (eroded(c) < 0.5_wp) cycle
          do j = 1, 2
            e = s%cell_elements(j, c)
            if (e > 0) s%live_cells(e) = s%live_cells(e) - 1
          end do
        end do
        if (s%contact%n > 0) call mortar_contact_erode(s%contact, s%live_cells)
        if (s%nodal_pressure) call nodal_reference_volumes(s, halo)
      end if
    end if
    call mortar_contact_restart_get(s%contact, f)
    call results_restart_get(f)
  contains
    !> Rigid body k's motion from its flat record.
    subroutine set_body(k, r)
      integer, intent(in) :: k                        !< body
      real(wp), intent(in) :: r(BODY_REALS)           !< its record
      associate (b => s%bodies%body(k))
        b%centre = r(1:3)
        b%centre_old = r(4:6)
        b%rotation = reshape(r(7:15), [3, 3])
        b%rotation_old = reshape(r(16:24), [3, 3])
        b%velocity = r(25:27)
        b%omega = r(28:30)
        b%angular_momentum = r(31:33)
        b%angle = r(34:36)
        b%reaction_force = r(37:39)
        b%reaction_moment = r(40:42)
        b%reaction_work = r(43)
        b%dt_last = r(44)
      end associate
    end subroutine set_body
  end subroutine explicit_restart_get

  !> Sizes that identify the model a restart file belongs to.
  function model_sizes(model, cells, layout, s) result(sizes)
    type(model_t), intent(in) :: model                !< resolved model
    type(cells_t), intent(in) :: cells                !< all cells
    type(explicit_layout_t), intent(in) :: layout     !< this rank's share
    type(explicit_state_t), intent(in) :: s           !< local state
    integer :: sizes(6)
    sizes = [model%nodes%n, model%elements%n, layout%nnode_global, cells%n, s%contact%n, &
             s%bodies%n]
  end function model_sizes

  !> Gather a nodal array (ncomp, local nodes) of the owned nodes in global node order on rank 0
  !> and write it.
  subroutine put_nodal(f, name, s, layout, ncomp, values)
    type(restart_file_t), intent(inout) :: f          !< file being written
    character(len=*), intent(in) :: name              !< record name
    type(explicit_state_t), intent(in) :: s           !< local state
    type(explicit_layout_t), intent(in) :: layout     !< this rank's share
    integer, intent(in) :: ncomp                      !< components per node
    real(wp), intent(in) :: values(:,:)               !< (ncomp, local nodes)
    integer :: l
    call put_rows(f, name, ncomp, layout%nnode_global, pack(s%node_global(1:s%nnode), &
                  s%owned(1:s%nnode)), values(:, pack([(l, l = 1, s%nnode)], s%owned)))
  end subroutine put_nodal

  !> Gather a cell array (ncomp, local cells) in global cell order on rank 0 and write it.
  subroutine put_cells(f, name, s, cells, ncomp, values)
    type(restart_file_t), intent(inout) :: f          !< file being written
    character(len=*), intent(in) :: name              !< record name
    type(explicit_state_t), intent(in) :: s           !< local state
    type(cells_t), intent(in) :: cells                !< all cells
    integer, intent(in) :: ncomp                      !< components per cell
    real(wp), intent(in) :: values(:,:)               !< (ncomp, local cells)
    call put_rows(f, name, ncomp, cells%n, s%cell_global(1:s%ncell), values(:, 1:s%ncell))
  end subroutine put_cells

  !> Gather rows (ncomp values each) with their global numbers on rank 0, place them in an
  !> array of nglobal rows (rows nobody sent stay 0) and write it.
  subroutine put_rows(f, name, ncomp, nglobal, rows, values)
    type(restart_file_t), intent(inout) :: f          !< file being written
    character(len=*), intent(in) :: name              !< record name
    integer, intent(in) :: ncomp                      !< values per row
    integer, intent(in) :: nglobal                    !< rows in the file
    integer, intent(in) :: rows(:)                    !< global rows of this rank's values
    real(wp), intent(in) :: values(:,:)               !< (ncomp, size(rows))
    integer, allocatable :: all_rows(:)
    real(wp), allocatable :: all_values(:), global(:,:)
    integer :: i
    call comm_gatherv_int(rows, all_rows)
    call comm_gatherv_real(reshape(values, [ncomp*size(rows)]), all_values)
    if (.not. comm_is_root()) return
    allocate(global(ncomp, nglobal))
    global = 0.0_wp
    do i = 1, size(all_rows)
      global(:, all_rows(i)) = all_values(ncomp*(i - 1) + 1:ncomp*i)
    end do
    call restart_put_reals(f, name, ncomp*nglobal, global)
  end subroutine put_rows

  !> Read a nodal array written by put_nodal into this rank's nodes.
  subroutine get_nodal(f, name, s, layout, ncomp, values)
    type(restart_file_t), intent(inout) :: f          !< file being read
    character(len=*), intent(in) :: name              !< record name
    type(explicit_state_t), intent(in) :: s           !< local state
    type(explicit_layout_t), intent(in) :: layout     !< this rank's share
    integer, intent(in) :: ncomp                      !< components per node
    real(wp), intent(inout) :: values(:,:)            !< (ncomp, local nodes)
    call get_rows(f, name, ncomp, layout%nnode_global, s%node_global(1:s%nnode), values)
  end subroutine get_nodal

  !> Read a cell array written by put_cells into this rank's cells.
  subroutine get_cells(f, name, s, cells, ncomp, values)
    type(restart_file_t), intent(inout) :: f          !< file being read
    character(len=*), intent(in) :: name              !< record name
    type(explicit_state_t), intent(in) :: s           !< local state
    type(cells_t), intent(in) :: cells                !< all cells
    integer, intent(in) :: ncomp                      !< components per cell
    real(wp), intent(inout) :: values(:,:)            !< (ncomp, local cells)
    call get_rows(f, name, ncomp, cells%n, s%cell_global(1:s%ncell), values)
  end subroutine get_cells

  !> Read a record of nglobal rows (ncomp values each) and keep the rows given.
  subroutine get_rows(f, name, ncomp, nglobal, rows, values)
    type(restart_file_t), intent(inout) :: f          !< file being read
    character(len=*), intent(in) :: name              !< record name
    integer, intent(in) :: ncomp                      !< values per row
    integer, intent(in) :: nglobal                    !< rows in the file
    integer, intent(in) :: rows(:)                    !< the global rows wanted
    real(wp), intent(inout) :: values(:,:)            !< (ncomp, size(rows))
    real(wp), allocatable :: global(:,:)
    integer :: l
    allocate(global(ncomp, nglobal))
    call restart_get_reals(f, name, size(global), global)
    do l = 1, size(rows)
      values(:, l) = global(:, rows(l))
    end do
  end subroutine get_rows

end module mefem_explicit_restart
