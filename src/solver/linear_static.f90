!> Linear static analysis (*CONTROL_IMPLICIT_GENERAL IMFLAG=1 with *CONTROL_IMPLICIT_SOLUTION
!> NSOLVR=1): small strain, isotropic elasticity, one solve with MUMPS.
!>
!>   K u = f,  K = sum_cells w G^T C G,  f from nodal loads and pressures at the end time,
!> with fixed and prescribed displacements eliminated (their columns moved to the right-hand
!> side); body loads (*LOAD_BODY_) are nodal forces -m a with the lumped masses of mesh and
!> enriched nodes (mefem_body_loads). Loads and prescribed motions are evaluated at the end time of
!> *CONTROL_TERMINATION (LS-DYNA's linear implicit step). Every rank assembles the cells of
!> its own elements; MUMPS solves on all ranks; every rank receives the whole solution.
module mefem_linear_static
  use mefem_kinds, only: wp
  use mefem_comm, only: comm_sum, comm_is_root, comm_wtime
  use mefem_errors, only: status_t, fatal, say
  use mefem_strings, only: itoa, rtoa
  use mefem_model, only: model_t, MAT_ELASTIC, ON_PART, TIEBREAK_NONE
  use mefem_decomposition, only: decomposition_t
  use mefem_cells, only: cells_t, cells_build, cells_summary, CELL_MAX_NODES
  use mefem_cell_linear, only: lame_parameters, cell_strain, isotropic_stress, cell_stiffness
  use mefem_hexahedron, only: hourglass_stiffness_cell
  use mefem_boundary_conditions, only: fixed_dofs, prescribed_displacements, external_forces
  use mefem_sparse_assembly, only: coo_matrix_t, coo_init, coo_add_block, coo_add_rectangle, &
                                   coo_free
  use mefem_implicit_nodal_pressure, only: np_patches_t, np_values_t, np_patches_build, &
                                           np_pairs_build, np_prepare, np_pressures, &
                                           np_cell_terms, np_add_to_pairs
  use mefem_implicit_constraints, only: node_constraints_t, constraints_set_up, &
                                        constraints_activate, constraints_residual, &
                                        constraints_matrix, constraints_increment
  use mefem_tied_contact, only: tied_nodes_t, tied_contact_build
  use mefem_mumps, only: mumps_solver_t, mumps_init, mumps_analyse, mumps_factorise, &
                         mumps_solve, mumps_free, mumps_stats, mumps_stats_t, MUMPS_SPD
  use mefem_output_mesh, only: output_field_t
  use mefem_results, only: results_write_state, append_node_set_fields
  use mefem_solver_common, only: number_equations, stress_fields
  use mefem_lumped_mass, only: lumped_mass
  use mefem_body_loads, only: body_acceleration, body_load_nodes, add_body_forces
  implicit none
  private

  public :: linear_static_run, cell_stresses


  !> Nodal-pressure tetrahedra (ELFORM 13): their patches (mefem_implicit_nodal_pressure). In
  !> the linear analysis the element is the F-bar form at u = 0: the deviatoric stiffness of
  !> the element and, on its patch, V0 K b b^T with b the gradient of its mean volumetric strain
  !> (doc/theory.md 2.7.1 at F = 1); the stress is 2 mu dev(eps) + pbar, pbar the patch mean
  !> of K tr(eps).
  type(np_patches_t) :: patches
contains

  !> Run the linear static analysis and write its results as output state 1.
  subroutine linear_static_run(model, decomp)
    type(model_t), intent(in) :: model              !< resolved model
    type(decomposition_t), intent(in) :: decomp     !< this rank's share
    type(cells_t) :: cells
    type(status_t) :: status
    type(coo_matrix_t) :: stiffness
    type(mumps_solver_t) :: solver
    type(mumps_stats_t) :: stats
    integer, allocatable :: equation(:,:)
    logical, allocatable :: fixed(:,:), owned_element(:)
    real(wp), allocatable :: prescribed(:,:), force(:,:), rhs(:), solution(:), u(:,:)
    type(node_constraints_t) :: skew
    type(tied_nodes_t) :: tied
    real(wp) :: t_end, t0, t_assembly
    integer :: dim, n_all, n_equations, i, n, k

    t0 = comm_wtime()
    call cells_build(model, cells, status, static=.true.)
    if (.not. status%ok) call fatal('element set-up: '//status%message)
    call check_supported(model, cells)
    call np_patches_build(cells, patches)
    dim = cells%dim
    n_all = cells%n_mesh_nodes + cells%n_enriched
    call cells_summary(cells)

    ! boundary conditions and loads at the end time
    t_end = model%controls%end_time
    if (t_end <= 0.0_wp) t_end = model%controls%dt0
    if (t_end <= 0.0_wp) call fatal('linear static analysis needs *CONTROL_TERMINATION ENDTIM '// &
        '(or *CONTROL_IMPLICIT_GENERAL DT0): the time at which loads and prescribed '// &
        'displacements are evaluated')
    allocate(fixed(dim, n_all), prescribed(dim, n_all), force(dim, n_all))
    fixed = .false.
    prescribed = 0.0_wp
    force = 0.0_wp
    call fixed_dofs(model, t_end, fixed(:, 1:cells%n_mesh_nodes))
    call prescribed_displacements(model, t_end, fixed(:, 1:cells%n_mesh_nodes), &
                                  prescribed(:, 1:cells%n_mesh_nodes))
    call external_forces(model, t_end, force(:, 1:cells%n_mesh_nodes))
    if (model%n_body_loads > 0) then
      block
        real(wp), allocatable :: mass(:)
        logical, allocatable :: loaded(:)
        call lumped_mass(model, cells, .false., mass)
        call body_load_nodes(model, cells, loaded)
        where (.not. loaded) mass = 0.0_wp
        call add_body_forces(body_acceleration(model, t_end), mass, force)
      end block
    end if
    ! tied contacts: a tied node's SPCs are overridden (it follows its masters); a driven tied
    ! node or master is refused
    if (model%n_ties > 0) then
      call tied_contact_build(model, tied, status)
      if (.not. status%ok) call fatal('linear static: '//status%message)
      block
        logical, allocatable :: spc_fixed(:,:)
        integer :: g
        allocate(spc_fixed(dim, cells%n_mesh_nodes))
        spc_fixed = .false.
        call fixed_dofs(model, t_end, spc_fixed)
        do g = 1, cells%n_mesh_nodes
          if (any(fixed(:, g) .and. .not. spc_fixed(:, g)) .and. (any(tied%slave == g) .or. &
              any(tied%master_node == g))) call fatal('linear static: node '// &
              itoa(model%nodes%id(g))//' of a tied contact has a prescribed motion: a tied '// &
              'node moves with its master facet; drive the bodies elsewhere')
        end do
      end block
      fixed(:, tied%slave) = .false.
    end if
    call number_equations(cells, fixed, equation, n_equations)
    call say('linear static: '//itoa(n_equations)//' equations')
    if (n_equations == 0) call fatal('linear static: every degree of freedom is fixed')

    ! assembly of this rank's cells: K_ff, and -K_fp u_p into the right-hand side
    allocate(owned_element(model%elements%n))
    owned_element = .false.
    owned_element(decomp%elem_global(1:decomp%nelem_local)) = .true.
    allocate(rhs(n_equations))
    rhs = 0.0_wp
    call assemble(model, cells, owned_element, equation, prescribed, stiffness, rhs)
    if (comm_is_root()) then      ! the loads once, on rank 0
      do n = 1, n_all
        do i = 1, dim
          if (equation(i, n) > 0) rhs(equation(i, n)) = rhs(equation(i, n)) + force(i, n)
        end do
      end do
    end if
    call comm_sum(rhs)
    ! SPCs in turned systems and tied contacts: a change of unknowns (mefem_implicit_constraints)
    if (model%n_ties > 0 .or. any([(model%spcs(k)%n_skew > 0, k = 1, model%n_spcs)])) then
      block
        logical, allocatable :: spc_fixed(:,:)
        type(coo_matrix_t) :: turned
        allocate(spc_fixed(dim, cells%n_mesh_nodes))
        spc_fixed = .false.
        call fixed_dofs(model, t_end, spc_fixed)
        if (model%n_ties > 0) spc_fixed(:, tied%slave) = .false.
        call constraints_set_up(model, equation, n_equations, &
                                fixed(:, 1:cells%n_mesh_nodes) .and. .not. spc_fixed, tied, skew)
        call constraints_activate(model, t_end, skew)
        call constraints_residual(skew, rhs)
        call constraints_matrix(skew, stiffness, turned)
        call coo_free(stiffness)
        stiffness = turned
        if (skew%n > 0) call say('linear static: '//itoa(skew%n)//' nodes with SPCs in '// &
                                 'turned systems (node frames)')
        if (model%n_ties > 0) call say('linear static: tied contacts hold '//itoa(tied%n)// &
                                       ' nodes')
      end block
    end if
    t_assembly = comm_wtime() - t0

    ! state 0: the unloaded model with every array of the solution's state
    block
      real(wp), allocatable :: zero(:,:)
      allocate(zero(dim, n_all))
      zero = 0.0_wp
      call write_results(model, decomp, cells, zero, 0.0_wp, 0)
    end block

    ! solve
    call mumps_init(solver, MUMPS_SPD, status)
    if (status%ok) call mumps_analyse(solver, stiffness, status)
    if (status%ok) call mumps_factorise(solver, stiffness, status)
    allocate(solution(n_equations))
    if (status%ok) call mumps_solve(solver, rhs, solution, status)
    if (.not. status%ok) call fatal('linear static: '//status%message)
    if (skew%active) call constraints_increment(skew, solution)      ! (back to global axes)
    stats = mumps_stats(solver)
    call say('linear static: set-up and assembly '//rtoa(t_assembly)//' s; MUMPS analysis '// &
             rtoa(stats%time_analysis)//' s, factorisation '// &
             rtoa(stats%time_factorisation)//' s, solve '// &
             rtoa(stats%time_solve)//' s, factor memory '// &
             itoa(stats%memory_total_mb)//' MB')
    call mumps_free(solver)
    call coo_free(stiffness)

    allocate(u(dim, n_all))
    u = prescribed
    do n = 1, n_all
      do i = 1, dim
        if (equation(i, n) > 0) u(i, n) = solution(equation(i, n))
      end do
    end do
    call write_results(model, decomp, cells, u, t_end, 1)
  end subroutine linear_static_run

  !> Linear static analysis takes *MAT_ELASTIC parts, displacement-type prescribed motions
  !> on nodes, and no contact (stopped with a message otherwise).
  subroutine check_supported(model, cells)
    type(model_t), intent(in) :: model    !< resolved model
    type(cells_t), intent(in) :: cells    !< cells
    integer :: c, k
    do c = 1, cells%n
      if (model%materials(cells%material(c))%kind /= MAT_ELASTIC) call fatal( &
          'linear static analysis (NSOLVR=1) needs *MAT_ELASTIC for every deformable part; '// &
          'material '//itoa(model%materials(cells%material(c))%id)//' is not')
    end do
    do k = 1, model%n_motions
      if (model%motions(k)%vad /= 2 .or. model%motions(k)%target_kind == ON_PART) call fatal( &
          'linear static analysis takes prescribed displacements (VAD=2) on nodes and node '// &
          'sets only; see *BOUNDARY_PRESCRIBED_MOTION at line '//itoa(model%motions(k)%src%line))
      if (abs(model%motions(k)%dof) == 4) call fatal('linear static analysis takes node '// &
          'motions along the global axes (DOF 1-3) only; DOF 4/-4 along a vector is explicit '// &
          'only; see *BOUNDARY_PRESCRIBED_MOTION at line '//itoa(model%motions(k)%src%line))
    end do
    do k = 1, model%n_spcs
      if (model%spcs(k)%n_skew > 0 .and. model%spcs(k)%moving_system > 0) call fatal( &
          'linear static analysis takes SPCs in fixed systems only; CID '// &
          itoa(model%spcs(k)%cid)//' moves with its nodes (FLAG 1: explicit only); see '// &
          '*BOUNDARY_SPC at line '//itoa(model%spcs(k)%src%line))
    end do
    if (model%n_contacts > 0 .or. model%n_rigid_walls > 0) call fatal( &
        'linear static analysis does not take contact or rigid walls')
    do k = 1, model%n_ties
      if (model%ties(k)%tiebreak /= TIEBREAK_NONE) call fatal('linear static analysis takes '// &
          'tied contacts that do not fail: a tiebreak is explicit only; see the contact at '// &
          'line '//itoa(model%ties(k)%src%line))
    end do
    if (model%n_rigid_constraints > 0) call fatal('linear static analysis does not take '// &
        '*CONSTRAINED_RIGID_BODIES or *CONSTRAINED_EXTRA_NODES (rigid parts take no part in it)')
  end subroutine check_supported

  !> Assemble the stiffness of the cells whose first element this rank owns.
  subroutine assemble(model, cells, owned_element, equation, prescribed, stiffness, rhs)
    type(model_t), intent(in) :: model                !< resolved model
    type(cells_t), intent(in) :: cells                !< cells
    logical, intent(in) :: owned_element(:)           !< element on this rank
    integer, intent(in) :: equation(:,:)              !< equation numbers
    real(wp), intent(in) :: prescribed(:,:)           !< prescribed displacements
    type(coo_matrix_t), intent(out) :: stiffness      !< this rank's entries (lower triangle)
    real(wp), intent(inout) :: rhs(:)                 !< -K_fp u_p added
    real(wp) :: ke(3*CELL_MAX_NODES, 3*CELL_MAX_NODES), up(3*CELL_MAX_NODES), lambda, mu
    real(wp) :: kh(3*CELL_MAX_NODES, 3*CELL_MAX_NODES), fh(3, CELL_MAX_NODES), energy
    real(wp), parameter :: zero(3, CELL_MAX_NODES) = 0.0_wp
    real(wp), parameter :: identity(3, 3) = reshape([1.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 1.0_wp, &
                                                     0.0_wp, 0.0_wp, 0.0_wp, 1.0_wp], [3, 3])
    integer :: dofs(3*CELL_MAX_NODES), c, nn, nd, dim, a, i, k, node, other
    integer :: n_owned
    type(np_values_t) :: values
    real(wp) :: tau(3, 3), c_eff(3, 3, 3, 3)
    real(wp), allocatable :: block(:,:), pair_values(:,:,:)
    dim = cells%dim
    allocate(block(3*patches%max_patch, 3*patches%max_patch))
    n_owned = count(owned_element(cells%elements(1, 1:cells%n)))
    call coo_init(stiffness, maxval(equation), int(n_owned, kind(1))*((dim*5)**2/2 + dim*5))
    if (patches%n > 0) call nodal_pressure_set_up()
    do c = 1, cells%n
      if (.not. owned_element(cells%elements(1, c))) cycle
      nn = cells%nnodes(c)
      nd = dim*nn
      call lame_parameters(model%materials(cells%material(c))%young, &
                           model%materials(cells%material(c))%poisson, lambda, mu)
      if (patches%n > 0) then
        if (patches%index_of(c) > 0) then       ! ELFORM 13: the deviatoric part here
          lambda = -2.0_wp*mu/3.0_wp
          call np_cell_terms(cells, patches, values, patches%index_of(c), tau, c_eff, block)
          call np_add_to_pairs(patches, patches%index_of(c), block, pair_values)
        end if
      end if
      call cell_stiffness(dim, nn, cells%grad(:, :, c), cells%weight(c), lambda, mu, &
                          ke(1:nd, 1:nd))
      if (cells%hex_of(c) > 0) then       ! one-point hexahedron: hourglass stiffness at u = 0
        call hourglass_stiffness_cell(nn, cells%grad(:, :, c), &
            cells%hg_gamma(:, :, cells%hex_of(c)), cells%hg_stiffness(:, cells%hex_of(c)), &
            zero, identity, fh(:, 1:nn), kh(1:nd, 1:nd), energy)
        ke(1:nd, 1:nd) = ke(1:nd, 1:nd) + kh(1:nd, 1:nd)
      end if
      do a = 1, nn
        do i = 1, dim
          dofs(dim*(a-1) + i) = equation(i, cells%nodes(a, c))
          up(dim*(a-1) + i) = prescribed(i, cells%nodes(a, c))
        end do
      end do
      call coo_add_block(stiffness, dofs(1:nd), ke(1:nd, 1:nd), .true.)
      ! prescribed columns to the right-hand side
      if (any(up(1:nd) /= 0.0_wp)) then
        do k = 1, nd
          if (dofs(k) > 0) rhs(dofs(k)) = rhs(dofs(k)) - dot_product(ke(k, 1:nd), &
              merge(up(1:nd), 0.0_wp, dofs(1:nd) <= 0))
        end do
      end if
    end do
    ! ELFORM 13: the patch blocks' sums, each node pair once (lower triangle), and their
    ! prescribed columns
    if (patches%n == 0) return
    do node = 1, size(patches%pair_start) - 1
      do k = patches%pair_start(node), patches%pair_start(node + 1) - 1
        other = patches%pair_node(k)
        call coo_add_rectangle(stiffness, equation(:, node), equation(:, other), &
                               pair_values(:, :, k), .true.)
        do i = 1, dim
          if (equation(i, node) <= 0) cycle
          do a = 1, dim
            if (equation(a, other) <= 0) rhs(equation(i, node)) = rhs(equation(i, node)) - &
                pair_values(i, a, k)*prescribed(a, other)
          end do
        end do
      end do
    end do

  contains

    !> The patches' node pairs of this rank's ELFORM 13 cells and their values at u = 0 with
    !> each cell's elastic tangent (K for the volumetric part, mu for the deviatoric).
    subroutine nodal_pressure_set_up()
      logical :: owned_cell(cells%n)
      real(wp) :: zero_u(3, cells%n_mesh_nodes + cells%n_enriched), lam, shear
      integer :: e, bad, p, q, r, t
      logical :: ok
      owned_cell = owned_element(cells%elements(1, 1:cells%n))
      call np_pairs_build(patches, owned_cell)
      allocate(pair_values(3, 3, size(patches%pair_node)))
      pair_values = 0.0_wp
      zero_u = 0.0_wp
      call np_prepare(cells, patches, zero_u, values, ok, bad)
      do e = 1, patches%n
        call lame_parameters(model%materials(cells%material(patches%cell(e)))%young, &
                             model%materials(cells%material(patches%cell(e)))%poisson, lam, &
                             shear)
        values%tau(:, :, e) = 0.0_wp
        do t = 1, 3
          do r = 1, 3
            do q = 1, 3
              do p = 1, 3
                values%c(p, q, r, t, e) = lam*merge(1.0_wp, 0.0_wp, p == q .and. r == t) + &
                    shear*(merge(1.0_wp, 0.0_wp, p == r .and. q == t) + &
                           merge(1.0_wp, 0.0_wp, p == t .and. q == r))
              end do
            end do
          end do
        end do
      end do
      call np_pressures(patches, values)
    end subroutine nodal_pressure_set_up

  end subroutine assemble

  !> Strain and stress of every cell (Voigt, stress xx yy zz xy yz zx).
  subroutine cell_stresses(model, cells, u, strain, stress)
    type(model_t), intent(in) :: model                 !< resolved model
    type(cells_t), intent(in) :: cells                 !< cells
    real(wp), intent(in) :: u(:,:)                     !< (dim, nodes) displacements
    real(wp), allocatable, intent(out) :: strain(:,:)  !< (6, cells) engineering shears
    real(wp), allocatable, intent(out) :: stress(:,:)  !< (6, cells)
    real(wp) :: lambda, mu
    type(np_values_t) :: values
    real(wp) :: bulk(patches%n)
    logical :: ok
    integer :: c, nn, e, bad, k
    allocate(strain(6, cells%n), stress(6, cells%n))
    if (patches%n > 0) then                     ! ELFORM 13: K tr(eps) per cell, then means
      call np_prepare(cells, patches, u(:, 1:size(u, 2)), values, ok, bad)
    end if
    do c = 1, cells%n
      nn = cells%nnodes(c)
      call lame_parameters(model%materials(cells%material(c))%young, &
                           model%materials(cells%material(c))%poisson, lambda, mu)
      call cell_strain(cells%dim, nn, cells%grad(:, :, c), u(:, cells%nodes(1:nn, c)), &
                       strain(:, c))
      if (patches%n > 0) then
        e = patches%index_of(c)
        if (e > 0) then                          ! its volumetric strain (a 'pressure' of 1)
          values%tau(:, :, e) = 0.0_wp
          do k = 1, 3
            values%tau(k, k, e) = sum(strain(1:3, c))
          end do
          values%jbar(e) = 1.0_wp
          bulk(e) = lambda + 2.0_wp*mu/3.0_wp
          lambda = -2.0_wp*mu/3.0_wp             ! the deviatoric stress
        end if
      end if
      call isotropic_stress(lambda, mu, strain(:, c), stress(:, c))
    end do
    if (patches%n == 0) return
    ! the pressure K (Jbar - 1) of each cell, Jbar - 1 the patch mean of the volumetric
    ! strain, and its patch mean again (the element's pbar, as in the nonlinear analyses)
    call np_pressures(patches, values)
    do e = 1, patches%n
      values%tau(:, :, e) = 0.0_wp
      do k = 1, 3
        values%tau(k, k, e) = bulk(e)*values%pbar(e)
      end do
    end do
    call np_pressures(patches, values)
    do e = 1, patches%n
      stress(1:3, patches%cell(e)) = stress(1:3, patches%cell(e)) + values%pbar(e)
    end do
  end subroutine cell_stresses

  !> Output state (1: the solution; 0: the unloaded model, which also carries the node sets):
  !> displacements at the deck's nodes, element stress (the mean of the element's cells),
  !> pressure and von Mises stress.
  subroutine write_results(model, decomp, cells, u, time, state)
    type(model_t), intent(in) :: model              !< resolved model
    type(decomposition_t), intent(in) :: decomp     !< this rank's share
    type(cells_t), intent(in) :: cells              !< cells
    real(wp), intent(in) :: u(:,:)                  !< (dim, nodes) displacements
    real(wp), intent(in) :: time                    !< analysis time of the state
    integer, intent(in) :: state                    !< output state number
    real(wp), allocatable :: strain(:,:), stress(:,:), element_stress(:,:), element_count(:)
    type(output_field_t), allocatable :: point_fields(:)
    type(output_field_t) :: cell_fields(3)
    real(wp), allocatable :: nodal_stress(:,:), nodal_weight(:)
    integer :: c, slot, e, local, a, node
    allocate(point_fields(4))
    call cell_stresses(model, cells, u, strain, stress)
    ! nodal values: the weight-averaged stress of the cells around each deck node
    allocate(nodal_stress(6, cells%n_mesh_nodes), nodal_weight(cells%n_mesh_nodes))
    nodal_stress = 0.0_wp
    nodal_weight = 0.0_wp
    do c = 1, cells%n
      do a = 1, cells%nnodes(c)
        node = cells%nodes(a, c)
        if (node > cells%n_mesh_nodes) cycle
        nodal_stress(:, node) = nodal_stress(:, node) + cells%weight(c)*stress(:, c)
        nodal_weight(node) = nodal_weight(node) + cells%weight(c)
      end do
    end do
    allocate(element_stress(6, model%elements%n), element_count(model%elements%n))
    element_stress = 0.0_wp
    element_count = 0.0_wp
    do c = 1, cells%n
      do slot = 1, 2
        e = cells%elements(slot, c)
        if (e == 0) cycle
        element_stress(:, e) = element_stress(:, e) + stress(:, c)
        element_count(e) = element_count(e) + 1.0_wp
      end do
    end do
    point_fields(1)%name = 'displacement'
    point_fields(1)%ncomp = 3
    allocate(point_fields(1)%values(3, decomp%nnode_local))
    point_fields(1)%values = 0.0_wp
    do local = 1, decomp%nnode_local
      point_fields(1)%values(1:cells%dim, local) = u(:, decomp%node_global(local))
    end do
    call stress_fields(nodal_stress(:, decomp%node_global(1:decomp%nnode_local)), &
                       nodal_weight(decomp%node_global(1:decomp%nnode_local)), point_fields(2:4))
    call stress_fields(element_stress(:, decomp%elem_global(1:decomp%nelem_local)), &
                       element_count(decomp%elem_global(1:decomp%nelem_local)), cell_fields)
    if (state == 0) call append_node_set_fields(model, decomp, point_fields)   ! state 0: the node sets
    call results_write_state(state, time, point_fields, cell_fields)
  end subroutine write_results

end module mefem_linear_static
