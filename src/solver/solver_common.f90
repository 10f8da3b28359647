!> Pieces shared by the analyses: equation numbering and the stress output fields.
module mefem_solver_common
  use mefem_kinds, only: wp
  use mefem_model, only: model_t, source_t
  use mefem_deck_source, only: location
  use mefem_errors, only: warn
  use mefem_strings, only: rtoa
  use mefem_decomposition, only: decomposition_t
  use mefem_cells, only: cells_t
  use mefem_output_mesh, only: output_field_t
  implicit none
  private

  public :: number_equations, stress_fields, cell_result_fields, schedule_after
  public :: warn_output_every_step, title_or_default, restart_files_due, first_dump_time

contains

  !> Equation numbers of the free degrees of freedom of the nodes that cells use (0 = fixed
  !> or unused), in node order.
  subroutine number_equations(cells, fixed, equation, n_equations)
    type(cells_t), intent(in) :: cells                   !< cells
    logical, intent(in) :: fixed(:,:)                    !< (dim, nodes) fixed dofs
    integer, allocatable, intent(out) :: equation(:,:)   !< (dim, nodes) equation numbers
    integer, intent(out) :: n_equations                  !< number of equations
    logical, allocatable :: used(:)
    integer :: c, n, i
    allocate(used(size(fixed, 2)), equation(size(fixed, 1), size(fixed, 2)))
    used = .false.
    do c = 1, cells%n
      used(cells%nodes(1:cells%nnodes(c), c)) = .true.
    end do
    equation = 0
    n_equations = 0
    do n = 1, size(fixed, 2)
      if (.not. used(n)) cycle
      do i = 1, size(fixed, 1)
        if (fixed(i, n)) cycle
        n_equations = n_equations + 1
        equation(i, n) = n_equations
      end do
    end do
  end subroutine number_equations

  !> Output fields 'stress' (6), 'pressure' = -tr/3 and 'von_mises' from summed stresses and
  !> their weights (entities with zero weight get zeros).
  subroutine stress_fields(stress_sum, weight, fields)
    real(wp), intent(in) :: stress_sum(:,:)            !< (6, n) weighted sums
    real(wp), intent(in) :: weight(:)                  !< (n) sums of the weights
    type(output_field_t), intent(inout) :: fields(3)   !< stress, pressure, von_mises
    integer :: k, n
    real(wp) :: s(6)
    n = size(weight)
    fields(1)%name = 'stress'
    fields(1)%ncomp = 6
    fields(2)%name = 'pressure'
    fields(3)%name = 'von_mises'
    allocate(fields(1)%values(6, n), fields(2)%values(1, n), fields(3)%values(1, n))
    do k = 1, n
      s = 0.0_wp
      if (weight(k) > 0.0_wp) s = stress_sum(:, k)/weight(k)
      fields(1)%values(:, k) = s
      fields(2)%values(1, k) = -(s(1) + s(2) + s(3))/3.0_wp
      fields(3)%values(1, k) = sqrt(0.5_wp*((s(1) - s(2))**2 + (s(2) - s(3))**2 + &
          (s(3) - s(1))**2) + 3.0_wp*(s(4)**2 + s(5)**2 + s(6)**2))
    end do
  end subroutine stress_fields

  !> Output fields of the cells' Cauchy stress and plastic strain: at this rank's nodes the
  !> cell-weight means of the cells touching the node ('stress', 'pressure', 'von_mises',
  !> 'plastic_strain'), at its elements the plain means of the element's cells (same names).
  !> The entries are every cell's (cell k at entry k) or those of cell_list, which must hold
  !> every cell of the piece's elements and every cell touching their nodes, ascending (each
  !> mean then adds its cells in the same order whatever the list: the same bits).
  subroutine cell_result_fields(model, decomp, cells, stress, alpha, point_fields, cell_fields, &
                                cell_list)
    type(model_t), intent(in) :: model                    !< resolved model
    type(decomposition_t), intent(in) :: decomp           !< this rank's output piece
    type(cells_t), intent(in) :: cells                    !< all cells
    real(wp), intent(in) :: stress(:,:)                   !< (6, entries) Cauchy stress (Voigt)
    real(wp), intent(in) :: alpha(:)                      !< (entries) equivalent plastic strain
    type(output_field_t), intent(inout) :: point_fields(4) !< nodal fields
    type(output_field_t), intent(inout) :: cell_fields(4)  !< element fields
    integer, intent(in), optional :: cell_list(:)         !< global cell of each entry
    real(wp), allocatable :: es(:,:), ew(:), ns(:,:), nw(:), alpha_e(:), alpha_n(:)
    integer, allocatable :: node_local(:), element_local(:)
    integer :: k, c, a, node, slot, e
    allocate(es(6, decomp%nelem_local), ew(decomp%nelem_local), ns(6, decomp%nnode_local), &
             nw(decomp%nnode_local), alpha_e(decomp%nelem_local), alpha_n(decomp%nnode_local))
    allocate(node_local(cells%n_mesh_nodes), element_local(model%elements%n))
    node_local = 0
    node_local(decomp%node_global(1:decomp%nnode_local)) = [(k, k = 1, decomp%nnode_local)]
    element_local = 0
    element_local(decomp%elem_global(1:decomp%nelem_local)) = [(k, k = 1, decomp%nelem_local)]
    es = 0.0_wp
    ew = 0.0_wp
    ns = 0.0_wp
    nw = 0.0_wp
    alpha_e = 0.0_wp
    alpha_n = 0.0_wp
    do k = 1, size(alpha)
      c = k
      if (present(cell_list)) c = cell_list(k)
      do slot = 1, 2
        if (cells%elements(slot, c) == 0) cycle
        e = element_local(cells%elements(slot, c))
        if (e == 0) cycle
        es(:, e) = es(:, e) + stress(:, k)
        ew(e) = ew(e) + 1.0_wp
        alpha_e(e) = alpha_e(e) + alpha(k)
      end do
      do a = 1, cells%nnodes(c)
        if (cells%nodes(a, c) > cells%n_mesh_nodes) cycle
        node = node_local(cells%nodes(a, c))
        if (node == 0) cycle
        ns(:, node) = ns(:, node) + cells%weight(c)*stress(:, k)
        nw(node) = nw(node) + cells%weight(c)
        alpha_n(node) = alpha_n(node) + cells%weight(c)*alpha(k)
      end do
    end do
    call stress_fields(ns, nw, point_fields(1:3))
    point_fields(4)%name = 'plastic_strain'
    point_fields(4)%values = reshape(merge(alpha_n/max(nw, tiny(1.0_wp)), 0.0_wp, &
                                           nw > 0.0_wp), [1, decomp%nnode_local])
    call stress_fields(es, ew, cell_fields(1:3))
    cell_fields(4)%name = 'plastic_strain'
    cell_fields(4)%values = reshape(merge(alpha_e/max(ew, tiny(1.0_wp)), 0.0_wp, &
                                          ew > 0.0_wp), [1, decomp%nelem_local])
  end subroutine cell_result_fields


  !> The deck's *TITLE, or "mefem" (the first line of the history files).
  pure function title_or_default(title) result(text)
    character(len=*), intent(in) :: title       !< *TITLE text (may be blank)
    character(len=:), allocatable :: text
    text = trim(title)
    if (len(text) == 0) text = 'mefem'
  end function title_or_default

  !> The first time of an output schedule (next, next + interval, ...) after t + tol, tol =
  !> 1e-9 interval, in one step: a loop of additions would take more than a run's cycles for
  !> an interval far below the step, and none would change next for one below t's resolution
  !> (a deck's DT of 1e-20). Below that resolution the result is the next number after t, so
  !> output falls due at every cycle or step.
  pure real(wp) function schedule_after(next, interval, t) result(after)
    real(wp), intent(in) :: next          !< the schedule's time just reached (or passed)
    real(wp), intent(in) :: interval      !< output interval (> 0)
    real(wp), intent(in) :: t             !< time reached
    real(wp) :: tol
    tol = 1.0e-9_wp*interval
    after = next
    if (after <= t + tol) after = next + (aint((t + tol - next)/interval) + 1.0_wp)*interval
    if (after <= t + tol) after = after + interval           ! (rounding of the ratio)
    if (.not. (after > t)) after = nearest(t, 1.0_wp)
  end function schedule_after

  !> A warning, naming the keyword and its line, for each output interval (D3PLOT, GLSTAT,
  !> RCFORC, NODOUT) below the smallest step the analysis takes (step: the explicit first
  !> step, the implicit DTMIN): such an interval cannot be kept, the output is written every
  !> cycle or step instead (schedule_after), which may be many more records than meant.
  subroutine warn_output_every_step(model, step, step_name, what, histories)
    type(model_t), intent(in) :: model                !< resolved model
    real(wp), intent(in) :: step                      !< the smallest step
    character(len=*), intent(in) :: step_name         !< what that step is, for the message
    character(len=*), intent(in) :: what              !< 'cycle' or 'step'
    logical, intent(in) :: histories                  !< the histories follow their DT too
                                                      !< (explicit; the implicit analysis
                                                      !< writes rcforc every step anyway)
    associate (c => model%controls)
      if (c%plot_count == 0) call check_one(c%plot_interval, c%plot_src, &
                                            '*DATABASE_BINARY_D3PLOT', 'result state')
      if (.not. histories) return
      call check_one(c%glstat_interval, c%glstat_src, '*DATABASE_GLSTAT', 'glstat record')
      call check_one(c%rcforc_interval, c%rcforc_src, '*DATABASE_RCFORC', 'rcforc record')
      call check_one(c%nodout_interval, c%nodout_src, '*DATABASE_NODOUT', 'nodout block')
    end associate

  contains

    !> The warning for one interval.
    subroutine check_one(interval, src, keyword, record)
      real(wp), intent(in) :: interval                !< the DT given (0: none)
      type(source_t), intent(in) :: src               !< where
      character(len=*), intent(in) :: keyword, record !< its keyword, what it writes
      if (interval <= 0.0_wp .or. interval >= step) return
      call warn(location(src%file, src%line)//': '//keyword//': DT = '//rtoa(interval)// &
                ' s is below '//step_name//' ('//rtoa(step)//' s): a '//record// &
                ' is written every '//what)
    end subroutine check_one

  end subroutine warn_output_every_step

  !> The restart files due after cycle (explicit) or converged step (implicit) n, at time t:
  !> a d3dump every *DATABASE_BINARY_D3DUMP CYCL and at every ENDTIM / NPLTC (next_dump, the
  !> next of those times, advanced), runrsf every *DATABASE_BINARY_RUNRSF CYCL.
  pure subroutine restart_files_due(model, n, t, next_dump, d3dump, runrsf)
    type(model_t), intent(in) :: model                !< resolved model
    integer, intent(in) :: n                          !< cycles or steps done
    real(wp), intent(in) :: t                         !< time reached
    real(wp), intent(inout) :: next_dump              !< next d3dump time (NPLTC)
    logical, intent(out) :: d3dump, runrsf            !< due
    real(wp) :: interval
    d3dump = .false.
    runrsf = .false.
    if (model%controls%d3dump_cycles > 0) d3dump = mod(n, model%controls%d3dump_cycles) == 0
    if (model%controls%d3dump_count > 0) then
      interval = model%controls%end_time/real(model%controls%d3dump_count, wp)
      if (t >= next_dump - 1.0e-9_wp*interval) then
        d3dump = .true.
        next_dump = schedule_after(next_dump, interval, t)
      end if
    end if
    if (model%controls%runrsf_cycles > 0) runrsf = mod(n, model%controls%runrsf_cycles) == 0
  end subroutine restart_files_due

  !> The first time *DATABASE_BINARY_D3DUMP's NPLTC asks for a restart file: ENDTIM / NPLTC
  !> (huge without NPLTC).
  pure real(wp) function first_dump_time(model)
    type(model_t), intent(in) :: model                !< resolved model
    first_dump_time = huge(1.0_wp)
    if (model%controls%d3dump_count > 0) first_dump_time = model%controls%end_time/ &
                                                           real(model%controls%d3dump_count, wp)
  end function first_dump_time

end module mefem_solver_common
