!> Contact of the nonlinear implicit analysis with rigid tools (mefem_implicit_static): the
!> tools' translations (*BOUNDARY_PRESCRIBED_MOTION_RIGID VAD = 2), the nodes that follow them
!> (*CONSTRAINED_EXTRA_NODES), the mortar contact's forces and its frozen-geometry tangent
!> (doc/theory.md 10) with Coulomb friction taken from the state of the last converged step,
!> and rcforc.
module mefem_implicit_tools
  use mefem_kinds, only: wp
  use mefem_comm, only: comm_is_root
  use mefem_errors, only: fatal, say
  use mefem_strings, only: itoa, rtoa
  use mefem_model, only: model_t, ON_PART, MAT_RIGID, RIGID_EXTRA_NODES
  use mefem_cells, only: cells_t
  use mefem_boundary_conditions, only: target_nodes
  use mefem_sparse_assembly, only: coo_matrix_t, coo_add_block
  use mefem_results, only: results_directory
  use mefem_solver_common, only: title_or_default
  use mefem_mortar_contact, only: mortar_contact_t, mortar_contact_setup, mortar_contact_forces, &
                                  mortar_contact_slave_rows
  use mefem_curves, only: curve_value
  use mefem_history_output, only: rcforc_open, rcforc_write
  implicit none
  private

  public :: set_up_tools, tool_displacement, extra_nodes_follow, tool_contact, report_contact

  !> Contact with rigid tools: the interfaces, and per mesh node the rigid part it belongs to
  !> (0: deformable) whose prescribed translation moves it.
  !> With friction, the interfaces' history (old mortar weights and normals, the tangential
  !> traction) is that of the last converged step: every Newton iteration starts from the
  !> committed copy, so the slip and the Coulomb return map are taken over the whole step,
  !> and the copy is renewed when a step converges.
  type, public :: tool_contact_t
    type(mortar_contact_t) :: interfaces
    type(mortar_contact_t) :: committed        !< state at the last converged step
    logical :: friction = .false.              !< some interface has FS > 0
    integer, allocatable :: rigid_part(:)      !< (mesh nodes) part index or 0
  end type tool_contact_t
  type(tool_contact_t), public :: tools           !< the tools' contact of the run
  !> Penalty of implicit contact relative to the explicit one (SLSFAC SFS K/h): statics has
  !> no time-step limit, so the penalty is 1000 x stiffer (100 K/h with SLSFAC = 0.1); the
  !> penetration is then about 1 % of the contact zone's elastic compression, and MUMPS's
  !> direct solve does not mind the conditioning.
  real(wp), parameter :: IMPLICIT_PENALTY_SCALE = 1000.0_wp
  !> A slave node whose tangential traction is within this fraction of mu p is sliding (the
  !> Coulomb return map puts it on mu p to round-off)
  real(wp), parameter :: SLIP_TOLERANCE = 1.0e-9_wp

contains

  !> Contact with rigid tools: the interfaces, the rigid part of every mesh node, rcforc.
  subroutine set_up_tools(model, cells, resume)
    type(model_t), intent(in) :: model                 !< resolved model
    type(cells_t), intent(in) :: cells                 !< cells (for the node count)
    logical, intent(in) :: resume                      !< a restart: rcforc is continued (opened
                                                       !< after the restart file is read)
    real(wp), allocatable :: no_mass(:)
    integer :: e, p, k
    allocate(tools%rigid_part(model%nodes%n))
    tools%rigid_part = 0
    do e = 1, model%elements%n
      p = model%elements%part(e)
      if (model%parts(p)%material <= 0) cycle
      if (model%materials(model%parts(p)%material)%kind /= MAT_RIGID) cycle
      where (model%elements%conn(:, e) > 0) tools%rigid_part(max(model%elements%conn(:, e), 1)) = p
    end do
    if (model%n_contacts == 0) return
    allocate(no_mass(cells%n_mesh_nodes))
    no_mass = 0.0_wp                   ! no time-step limit of the penalty in statics
    call mortar_contact_setup(model, no_mass, tools%interfaces)
    if (any(tools%rigid_part(tools%interfaces%node_global) == 0 .and. is_master_node())) &
      call fatal('implicit analysis takes contact with rigid tools only (SURFB must be a '// &
                 'rigid part)')
    ! Coulomb friction: quasi-static pseudo-time has no sliding velocity, so the decay of
    ! *CONTACT's DC is not applied (mu = FS)
    do k = 1, tools%interfaces%n
      associate (it => tools%interfaces%interfaces(k))
        call say('implicit: contact '//itoa(it%id)//': normal penalty '// &
            rtoa(IMPLICIT_PENALTY_SCALE*it%eps_material)//', tangential penalty '// &
            rtoa(it%eps_material)//' (pressure per unit gap or slip)')
        if (it%dc > 0.0_wp) call say('implicit: contact '//itoa(it%id)//': DC ignored in '// &
            'statics (no sliding velocity): mu = FS = '//rtoa(it%fs))
        it%dc = 0.0_wp
        if (it%fs > 0.0_wp) tools%friction = .true.
      end associate
    end do
    if (tools%friction) tools%committed = tools%interfaces
    if (model%controls%rcforc_interval > 0.0_wp .and. .not. resume) &
      call rcforc_open(results_directory(), title_or_default(model%controls%title))
  contains
    !> Contact nodes on a master surface.
    function is_master_node() result(mask)
      logical :: mask(tools%interfaces%nnode)
      integer :: k
      mask = .false.
      do k = 1, tools%interfaces%n
        mask(tools%interfaces%node_index(tools%interfaces%interfaces(k)%master%nodes)) = .true.
      end do
    end function is_master_node
  end subroutine set_up_tools

  !> Translation of rigid part p at time t: its *BOUNDARY_PRESCRIBED_MOTION_RIGID VAD=2 (0
  !> before BIRTH, held at the DEATH value after it).
  function tool_displacement(model, p, t) result(d)
    type(model_t), intent(in) :: model                 !< resolved model
    integer, intent(in) :: p                           !< part index
    real(wp), intent(in) :: t                          !< time
    real(wp) :: d(3)
    integer :: k
    d = 0.0_wp
    do k = 1, model%n_motions
      associate (pm => model%motions(k))
        if (pm%target_kind /= ON_PART .or. pm%target /= p) cycle
        if (t < pm%birth) cycle
        ! after DEATH the tool stays where the motion left it
        d(pm%dof) = pm%scale*curve_value(model%curves(pm%curve), min(t, pm%death))
      end associate
    end do
  end function tool_displacement

  !> *CONSTRAINED_EXTRA_NODES: the extra nodes of a rigid tool are driven with it (the tools
  !> translate in the implicit analysis): all their dofs fixed, with the tool's displacement
  !> at t.
  subroutine extra_nodes_follow(model, t, fixed, value)
    type(model_t), intent(in) :: model                 !< resolved model
    real(wp), intent(in) :: t                          !< time
    logical, intent(inout) :: fixed(:,:)               !< (dim, mesh nodes) fixed dofs
    real(wp), intent(inout) :: value(:,:)              !< (dim, mesh nodes) their values
    integer, allocatable :: nodes(:)
    real(wp) :: d(3)
    integer :: k, i
    do k = 1, model%n_rigid_constraints
      associate (rc => model%rigid_constraints(k))
        if (rc%kind /= RIGID_EXTRA_NODES .or. rc%lead <= 0 .or. rc%target <= 0) cycle
        call target_nodes(model, rc%target_kind, rc%target, nodes)
        d = tool_displacement(model, rc%lead, t)
        do i = 1, size(nodes)
          fixed(:, nodes(i)) = .true.
          value(:, nodes(i)) = d(1:size(value, 1))
        end do
      end associate
    end do
  end subroutine extra_nodes_follow

  !> Contact forces and their frozen-geometry penalty tangent (formulation 5.5) at u and the
  !> tools' positions at t: residual += contact forces at the free slave dofs, tangent +=
  !> eps/A_A (w_A w_A^T) (x) K_A for every penetrating slave node, K_A = n_A n_A^T when
  !> frictionless, n_A n_A^T + (I - n_A n_A^T)/IMPLICIT_PENALTY_SCALE when sticking (the
  !> tangential penalty is the explicit one), n_A n_A^T - mu d_A n_A^T when sliding along d_A. Every rank computes the
  !> same contact; rank 0 adds it (the residual is summed over ranks, the matrix input is
  !> distributed).
  subroutine tool_contact(model, cells, equation, u, t, residual, tangent)
    type(model_t), intent(in) :: model                 !< resolved model
    type(cells_t), intent(in) :: cells                 !< cells
    integer, intent(in) :: equation(:,:)               !< equation numbers
    real(wp), intent(in) :: u(:,:)                     !< displacements
    real(wp), intent(in) :: t                          !< time of u
    real(wp), intent(inout) :: residual(:)             !< free-dof residual (rank 0 adds)
    type(coo_matrix_t), intent(inout) :: tangent       !< tangent (rank 0 adds)
    integer, allocatable :: start(:), nodes(:), dofs(:)
    real(wp), allocatable :: weights(:), ke(:,:)
    real(wp) :: coef, nn(3, 3), d(3), magnitude, limit
    integer :: k, g, dim, a, i, j, m, b1, b2
    dim = cells%dim
    if (tools%friction) tools%interfaces = tools%committed
    associate (c => tools%interfaces)
      do k = 1, c%nnode
        g = c%node_global(k)
        c%x(:, g) = model%nodes%x(:, g)
        if (tools%rigid_part(g) > 0) then
          c%x(:, g) = c%x(:, g) + tool_displacement(model, tools%rigid_part(g), t)
        else
          c%x(1:dim, g) = c%x(1:dim, g) + u(:, g)
        end if
      end do
      call mortar_contact_forces(c, 0.0_wp, IMPLICIT_PENALTY_SCALE, time=t)
      if (.not. comm_is_root()) return
      do k = 1, c%nnode
        g = c%node_global(k)
        if (tools%rigid_part(g) > 0) cycle
        do i = 1, dim
          if (equation(i, g) > 0) residual(equation(i, g)) = residual(equation(i, g)) + &
              c%force(i, k)
        end do
      end do
      do k = 1, c%n
        associate (it => c%interfaces(k))
          call mortar_contact_slave_rows(c, k, start, nodes, weights)
          do a = 1, size(it%slave%nodes)
            if (it%pressure(a) <= 0.0_wp .or. it%gap(a) >= 0.0_wp) cycle
            coef = it%pressure(a)/(-it%gap(a))/it%area(a)
            m = start(a + 1) - start(a)
            allocate(ke(dim*m, dim*m), dofs(dim*m))
            ! nn: the node's 3x3 block per unit coef w_aB w_aB'
            do i = 1, dim
              do j = 1, dim
                nn(i, j) = it%normal(i, a)*it%normal(j, a)
              end do
            end do
            if (it%fs > 0.0_wp .and. it%area_old(a) > 0.0_wp) then
              limit = it%fs*it%pressure(a)
              magnitude = norm2(it%traction(:, a))
              if (magnitude < (1.0_wp - SLIP_TOLERANCE)*limit) then
                ! sticking: the tangential penalty is the normal one / IMPLICIT_PENALTY_SCALE
                do i = 1, dim
                  nn(i, i) = nn(i, i) + 1.0_wp/IMPLICIT_PENALTY_SCALE
                  do j = 1, dim
                    nn(i, j) = nn(i, j) - it%normal(i, a)*it%normal(j, a)/IMPLICIT_PENALTY_SCALE
                  end do
                end do
              else
                ! sliding: t = mu p d; the pressure's share (mu d n^T); the turn of d
                ! within the tangent plane (3D) is left out of this tangent
                d = it%traction(:, a)/magnitude
                do i = 1, dim
                  do j = 1, dim
                    nn(i, j) = nn(i, j) - it%fs*d(i)*it%normal(j, a)
                  end do
                end do
              end if
            end if
            do b1 = 1, m
              do i = 1, dim
                dofs(dim*(b1 - 1) + i) = equation(i, nodes(start(a) + b1 - 1))
              end do
              do b2 = 1, m
                ke(dim*(b1 - 1) + 1:dim*b1, dim*(b2 - 1) + 1:dim*b2) = coef* &
                    weights(start(a) + b1 - 1)*weights(start(a) + b2 - 1)*nn(1:dim, 1:dim)
              end do
            end do
            call coo_add_block(tangent, dofs, ke, .false.)
            deallocate(ke, dofs)
          end do
        end associate
      end do
    end associate
  end subroutine tool_contact

  !> After a converged step: the tools' contact forces in the log (and rcforc, every step,
  !> when *DATABASE_RCFORC is given).
  subroutine report_contact(t, write_rcforc)
    real(wp), intent(in) :: t                          !< time of the step
    logical, intent(in) :: write_rcforc                !< *DATABASE_RCFORC given
    integer :: k
    do k = 1, tools%interfaces%n
      associate (it => tools%interfaces%interfaces(k))
        call say('  contact '//itoa(it%id)//': normal force '//rtoa(it%normal_force)// &
                 ', force on the tool '//rtoa(it%force_master(1))//' '// &
                 rtoa(it%force_master(2))//' '//rtoa(it%force_master(3)))
        if (write_rcforc) call rcforc_write(t, it%id, it%force_slave, it%force_master, &
                                            it%normal_force, it%tangential_force)
      end associate
    end do
  end subroutine report_contact

end module mefem_implicit_tools
