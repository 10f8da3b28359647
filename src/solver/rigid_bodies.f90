!> Rigid bodies of *MAT_RIGID parts for the explicit solver (doc/theory.md, "Rigid bodies and
!> rigid walls").
!>
!> One body per *MAT_RIGID part, or per group of them merged by *CONSTRAINED_RIGID_BODIES (the
!> lead part's constraints), with the nodes *CONSTRAINED_EXTRA_NODES adds; and one body of
!> nodes per *CONSTRAINED_NODAL_RIGID_BODY (a node set) and *CONSTRAINED_SPOTWELD (two nodes),
!> with the nodes' masses only. Its mass, centre of mass and inertia tensor come from the
!> part's elements (solids split into tetrahedra, shells as plates of thickness T1; in 2D
!> plane strain, shells of unit thickness) plus the lumped masses of deformable elements at
!> the body's nodes ("merged" nodes belong to the body). The state of body b is its centre
!> x_c, rotation R (reference -> current), translational velocity v and spatial angular
!> velocity omega at half steps, and its spatial angular momentum L. One step of the central
!> difference scheme (rigid_bodies_advance), with the resultant force F and moment M about
!> x_c at t^n:
!>   v^{n+1/2} = v^{n-1/2} + dt_avg F/m,            x_c^{n+1} = x_c^n + dt_new v^{n+1/2}
!>   L^{n+1/2} = L^{n-1/2} + dt_avg M,              omega^{n+1/2} = I_mid^{-1} L^{n+1/2}
!>   R^{n+1} = exp(dt_new [omega^{n+1/2}]x) R^n     (Rodrigues' formula)
!> with I_mid = R_mid I_0 R_mid^T at the mid-step rotation R_mid = exp(dt_new/2 [omega]x) R^n,
!> found by MIDPOINT_CORRECTIONS fixed-point passes that start from I_n = R^n I_0 R^nT (zero
!> passes is the plain I_n scheme, first order in R; the mid-step inertia makes it second
!> order). L is exactly conserved without moments. Constraints (CON1/CON2 of *MAT_RIGID with
!> CMO = 1) and *BOUNDARY_PRESCRIBED_MOTION_RIGID (VAD 0 velocity, 1 acceleration,
!> 2 displacement; DOF 1-3 translations of the centre of mass, 5-7 rotations about the
!> global axes) replace the corresponding components of v or omega; the free components of
!> omega then solve the free rows of I_mid omega = L. The reaction is what the constraints
!> had to add to the applied load: m (v^{n+1/2} - v^{n-1/2})/dt_avg - F on the constrained
!> translations, (I_mid omega^{n+1/2} - L^{n-1/2})/dt_avg - M on the constrained rotations.
!> In 2D only x, y and the rotation about z exist (z and the rotations about x, y are held).
!>
!> The data are small and replicated: every rank calls these routines identically (no MPI
!> here); the driver sums force and moment over the ranks before rigid_bodies_advance.
module mefem_rigid_bodies
  use mefem_kinds, only: wp
  use mefem_errors, only: status_t, say
  use mefem_strings, only: itoa
  use mefem_vector_math, only: cross
  use mefem_tensor_algebra, only: determinant, inverse
  use mefem_model, only: model_t, VAD_VELOCITY, VAD_ACCELERATION, VAD_DISPLACEMENT, &
                         MAT_RIGID, ELEM_SOLID, ON_PART, ON_NODE, RIGID_MERGE, &
                         RIGID_EXTRA_NODES, RIGID_NODAL, TOPO_TRI3, TOPO_QUAD4, &
                         TOPO_TET4, TOPO_PENTA6, TOPO_HEX8
  use mefem_curves, only: curve_value
  implicit none
  private

  public :: rigid_bodies_build, rigid_bodies_set_velocity, rigid_bodies_accumulate, &
            rigid_body_velocity_fit, &
            rigid_bodies_advance, rigid_body_point_motion, rigid_bodies_kinetic_energy, &
            rigid_body_reaction

  !> DOF 5-7 (rotations about x, y, z) are slots 4-6 of the (v, omega) vector.
  integer, parameter :: ROTATION_DOF_SHIFT = 1
  !> CON1/CON2 code of *MAT_RIGID (CMO = 1) -> held x, y, z (translations or rotations):
  !> 0 none, 1 x, 2 y, 3 z, 4 x and y, 5 y and z, 6 z and x, 7 all (as the TC code of *NODE).
  logical, parameter :: CODE_HELD(3, 0:7) = reshape([ &
      .false., .false., .false.,  .true., .false., .false.,  .false., .true., .false., &
      .false., .false., .true.,   .true., .true., .false.,   .false., .true., .true., &
      .true., .false., .true.,    .true., .true., .true.], [3, 8])
  !> Fixed-point passes for the mid-step inertia (0: inertia at t^n, first order in R).
  integer, parameter :: MIDPOINT_CORRECTIONS = 2
  !> A pivot of the free inertia block below this fraction of its largest diagonal entry
  !> makes it singular (a free rotation without inertia).
  real(wp), parameter :: SINGULAR_PIVOT = 1.0e-12_wp
  !> Below this rotation angle (rad) Rodrigues' coefficients use their Taylor series
  !> (next neglected term theta^6/5040 < 2e-16).
  real(wp), parameter :: SMALL_ANGLE = 1.0e-2_wp
  real(wp), parameter :: IDENTITY(3, 3) = reshape([1.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 1.0_wp, &
                                                   0.0_wp, 0.0_wp, 0.0_wp, 1.0_wp], [3, 3])
  !> Tetrahedra of a pentahedron (wedge, output order: triangles 1-2-3 and 4-5-6, 4 over 1).
  integer, parameter :: PENTA_TETS(4, 3) = reshape([1, 2, 3, 4,  2, 3, 4, 5,  3, 4, 5, 6], &
                                                   [4, 3])
  !> Tetrahedra of a hexahedron (output order, 5-8 over 1-4), around the diagonal 1-7.
  integer, parameter :: HEX_TETS(4, 6) = reshape([1, 2, 3, 7,  1, 3, 4, 7,  1, 4, 8, 7, &
                                                  1, 8, 5, 7,  1, 5, 6, 7,  1, 6, 2, 7], [4, 6])
  !> Triangles of a quadrilateral.
  integer, parameter :: QUAD_TRIANGLES(3, 2) = reshape([1, 2, 3,  1, 3, 4], [3, 2])

  !> One rigid body. Vectors are 3-vectors in 2D as well (z components zero).
  type, public :: rigid_body_t
    integer :: part = 0                         !< part index (0: a body of nodes)
    integer :: id = 0                           !< its number (rbdout, messages): the part id,
                                                !< or the nodal body's PID/SWID, else the
                                                !< largest part id plus its position
    real(wp) :: mass = 0.0_wp                   !< total mass (elements + merged nodes)
    real(wp) :: centre0(3) = 0.0_wp             !< centre of mass, reference configuration
    real(wp) :: centre(3) = 0.0_wp              !< centre of mass at t^{n+1}
    real(wp) :: centre_old(3) = 0.0_wp          !< centre of mass at t^n
    real(wp) :: inertia0(3, 3) = 0.0_wp         !< inertia tensor about centre0, reference
    real(wp) :: rotation(3, 3) = IDENTITY       !< R at t^{n+1}: x = centre + R (x0 - centre0)
    real(wp) :: rotation_old(3, 3) = IDENTITY   !< R at t^n
    real(wp) :: velocity(3) = 0.0_wp            !< centre velocity at t^{n+1/2}
    real(wp) :: omega(3) = 0.0_wp               !< spatial angular velocity at t^{n+1/2}
    real(wp) :: angular_momentum(3) = 0.0_wp    !< spatial L about the centre at t^{n+1/2}
    real(wp) :: angle(3) = 0.0_wp               !< time integral of omega (rotation about
                                                !< the global axes, for VAD = 2) at t^{n+1}
    logical :: held_translation(3) = .false.    !< CON1 (and z in 2D)
    logical :: held_rotation(3) = .false.       !< CON2 (and x, y in 2D)
    real(wp) :: reaction_force(3) = 0.0_wp      !< constraint force of the last advance (t^n)
    real(wp) :: reaction_moment(3) = 0.0_wp     !< constraint moment about the centre
    real(wp) :: reaction_work = 0.0_wp          !< work of the reactions so far
    real(wp) :: dt_last = 0.0_wp                !< dt_new of the last advance (0: none yet)
  end type rigid_body_t

  !> All rigid bodies of a model.
  type, public :: rigid_bodies_t
    integer :: n = 0                            !< number of bodies
    integer :: dim = 3                          !< 2 (plane strain) or 3
    type(rigid_body_t), allocatable :: body(:)  !< (n)
    integer, allocatable :: node_body(:)        !< (n_mesh_nodes) body of a node, 0 = none
    integer, allocatable :: body_of_part(:)     !< (n_parts) body of a part, 0 = deformable
  end type rigid_bodies_t

contains

  ! ------------------------------------------------------------------ building

  !> One body per *MAT_RIGID part: nodes, mass, centre, inertia, constraint flags; checks the
  !> prescribed motions. merged_mass(n_mesh_nodes) are the deformable lumped masses, added as
  !> point masses at the body's nodes. Fails (status) when a node belongs to two rigid parts,
  !> a 2D model has rigid solids, a motion has a DOF or VAD this module does not take, or a
  !> free degree of freedom (not held, not prescribed) has no mass or inertia.
  subroutine rigid_bodies_build(model, merged_mass, bodies, status)
    type(model_t), intent(in) :: model            !< resolved model
    real(wp), intent(in) :: merged_mass(:)        !< (n_mesh_nodes) deformable lumped masses
    type(rigid_bodies_t), intent(out) :: bodies   !< the bodies, at rest in the reference
    type(status_t), intent(out) :: status         !< failure and why
    integer :: p, b, e, i, node, m, k, n_part_bodies, largest_id
    integer, allocatable :: lead(:), extra(:)
    real(wp) :: mass, first(3), second(3, 3), origin(3)
    real(wp), allocatable :: body_mass(:), body_first(:,:), body_second(:,:,:), body_origin(:,:)
    logical, allocatable :: seen(:)

    status%ok = .true.
    bodies%dim = model%dimension
    if (size(merged_mass) /= model%nodes%n) then
      call fail(status, 'rigid bodies: merged_mass has '//itoa(size(merged_mass))// &
          ' entries for '//itoa(model%nodes%n)//' nodes')
      return
    end if
    allocate(bodies%body_of_part(model%n_parts), bodies%node_body(model%nodes%n))
    bodies%body_of_part = 0
    bodies%node_body = 0
    bodies%n = 0
    ! *CONSTRAINED_RIGID_BODIES: a merged part takes the body of its lead part (chains
    ! followed: the body is that of the part at the head of the chain)
    allocate(lead(model%n_parts))
    lead = [(p, p = 1, model%n_parts)]
    do k = 1, model%n_rigid_constraints
      associate (rc => model%rigid_constraints(k))
        if (rc%kind /= RIGID_MERGE .or. rc%lead <= 0 .or. rc%target <= 0) cycle
        lead(head(rc%target)) = head(rc%lead)
      end associate
    end do
    do p = 1, model%n_parts
      m = model%parts(p)%material
      if (m <= 0) cycle
      if (model%materials(m)%kind /= MAT_RIGID) cycle
      if (head(p) /= p) cycle
      bodies%n = bodies%n + 1
      bodies%body_of_part(p) = bodies%n
    end do
    do p = 1, model%n_parts
      if (head(p) /= p) bodies%body_of_part(p) = bodies%body_of_part(head(p))
    end do
    n_part_bodies = bodies%n
    do k = 1, model%n_rigid_constraints
      if (model%rigid_constraints(k)%kind == RIGID_NODAL) bodies%n = bodies%n + 1
    end do
    allocate(bodies%body(bodies%n))
    do p = 1, model%n_parts
      b = bodies%body_of_part(p)
      if (b == 0 .or. head(p) /= p) cycle
      bodies%body(b)%part = p
      bodies%body(b)%id = model%parts(p)%id
      m = model%parts(p)%material
      if (model%materials(m)%cmo == 1) then
        bodies%body(b)%held_translation = CODE_HELD(:, model%materials(m)%con1)
        bodies%body(b)%held_rotation = CODE_HELD(:, model%materials(m)%con2)
      end if
      if (bodies%dim == 2) then
        bodies%body(b)%held_translation(3) = .true.
        bodies%body(b)%held_rotation(1:2) = .true.
      end if
    end do

    ! bodies of nodes: their numbers (the 2D holds as for parts)
    b = n_part_bodies
    largest_id = 0
    if (model%n_parts > 0) largest_id = maxval(model%parts(1:model%n_parts)%id)
    do k = 1, model%n_rigid_constraints
      if (model%rigid_constraints(k)%kind /= RIGID_NODAL) cycle
      b = b + 1
      bodies%body(b)%id = model%rigid_constraints(k)%lead_id
      if (bodies%body(b)%id <= 0) bodies%body(b)%id = largest_id + b - n_part_bodies
      if (bodies%dim == 2) then
        bodies%body(b)%held_translation(3) = .true.
        bodies%body(b)%held_rotation(1:2) = .true.
      end if
    end do

    ! nodes of each body; the first node seen is the origin of the first moments
    allocate(body_origin(3, bodies%n), seen(bodies%n))
    seen = .false.
    body_origin = 0.0_wp
    do e = 1, model%elements%n
      b = bodies%body_of_part(model%elements%part(e))
      if (b == 0) cycle
      if (bodies%dim == 2 .and. model%elements%keyword(e) == ELEM_SOLID) then
        call fail(status, body_name(bodies, b)//': element '//itoa(model%elements%id(e))//' is a solid in a 2D (plane strain) '// &
            'model')
        return
      end if
      do i = 1, size(model%elements%conn, 1)
        node = model%elements%conn(i, e)
        if (node <= 0) cycle
        if (.not. joined(node, b, '')) return
      end do
    end do
    ! *CONSTRAINED_EXTRA_NODES: the nodes join the body of their part
    do k = 1, model%n_rigid_constraints
      associate (rc => model%rigid_constraints(k))
        if (rc%kind /= RIGID_EXTRA_NODES .or. rc%lead <= 0 .or. rc%target <= 0) cycle
        b = bodies%body_of_part(rc%lead)
        if (b == 0) cycle
        if (rc%target_kind == ON_NODE) then
          extra = [rc%target]
        else
          extra = model%sets(rc%target)%members
        end if
        do i = 1, size(extra)
          node = extra(i)
          if (node <= 0) cycle
          if (.not. joined(node, b, '*CONSTRAINED_EXTRA_NODES: ')) return
        end do
      end associate
    end do

    ! *CONSTRAINED_NODAL_RIGID_BODY, *CONSTRAINED_SPOTWELD: their nodes form the body
    b = n_part_bodies
    do k = 1, model%n_rigid_constraints
      associate (rc => model%rigid_constraints(k))
        if (rc%kind /= RIGID_NODAL) cycle
        b = b + 1
        if (rc%target_kind == ON_NODE) then
          extra = [rc%target, rc%second]
        else if (rc%target > 0) then
          extra = model%sets(rc%target)%members
        else
          extra = [integer ::]
        end if
        do i = 1, size(extra)
          node = extra(i)
          if (node <= 0) cycle
          if (.not. joined(node, b, '')) return
        end do
      end associate
    end do

    ! pass 1: mass and centre; pass 2: second moments about the centre
    allocate(body_mass(bodies%n), body_first(3, bodies%n), body_second(3, 3, bodies%n))
    call sum_moments(body_origin)
    do b = 1, bodies%n
      associate (body => bodies%body(b))
        body%mass = body_mass(b)
        if (body_mass(b) > 0.0_wp) then
          body%centre0 = body_origin(:, b) + body_first(:, b)/body_mass(b)
        else
          body%centre0 = body_origin(:, b)
        end if
        body_origin(:, b) = body%centre0
      end associate
    end do
    call sum_moments(body_origin)
    do b = 1, bodies%n
      associate (body => bodies%body(b))
        second = body_second(:, :, b)
        ! inertia J = tr(S) 1 - S of the second moment S = sum m r r^T
        body%inertia0 = -second
        do i = 1, 3
          body%inertia0(i, i) = body%inertia0(i, i) + second(1, 1) + second(2, 2) + second(3, 3)
        end do
        ! a body of nodes on a line (a spot weld) or at one point has no inertia about the
        ! line (about any axis): its spin there moves none of its nodes, and no nodal force
        ! has a moment about it; the inertia tr(S) 1 (a line's transverse inertia about every
        ! axis; a point's mass times the unit length squared) keeps the equations regular
        if (b > n_part_bodies .and. singular_inertia(body%inertia0)) then
          body%inertia0 = 0.0_wp
          do i = 1, 3
            body%inertia0(i, i) = second(1, 1) + second(2, 2) + second(3, 3)
            if (.not. body%inertia0(i, i) > 0.0_wp) body%inertia0(i, i) = body%mass
          end do
        end if
        ! *PART_INERTIA: the mass, centre and inertia given replace those of the elements and
        ! of the masses merged at the body's nodes
        if (body%part > 0) then
          associate (part => model%parts(body%part))
            if (part%has_inertia) then
              body%mass = part%inertia_mass
              body%centre0 = part%inertia_centre
              if (part%inertia_node > 0) body%centre0 = model%nodes%x(:, part%inertia_node)
              body%inertia0 = reshape([part%inertia_tensor(1), part%inertia_tensor(2), &
                  part%inertia_tensor(3), part%inertia_tensor(2), part%inertia_tensor(4), &
                  part%inertia_tensor(5), part%inertia_tensor(3), part%inertia_tensor(5), &
                  part%inertia_tensor(6)], [3, 3])
            end if
          end associate
        end if
        body%centre = body%centre0
        body%centre_old = body%centre0
      end associate
    end do
    ! a part merged into another's body (*CONSTRAINED_RIGID_BODIES) cannot give the body's mass
    do p = 1, model%n_parts
      if (.not. model%parts(p)%has_inertia) cycle
      b = bodies%body_of_part(p)
      if (b == 0) cycle
      if (bodies%body(b)%part /= p) then
        call fail(status, 'part '//itoa(model%parts(p)%id)//' has *PART_INERTIA but is merged '// &
            'into the '//body_name(bodies, b)//' (*CONSTRAINED_RIGID_BODIES): give the mass '// &
            'properties of the whole body on its lead part')
        return
      end if
    end do
    call check_motions(model, bodies, status)

  contains

    !> Node joins body b (the first node of a body is the origin of its first moments);
    !> false (status failed) when it belongs to another body already.
    logical function joined(node, b, who)
      integer, intent(in) :: node, b              !< node and body
      character(len=*), intent(in) :: who         !< message prefix
      joined = .true.
      if (bodies%node_body(node) /= 0 .and. bodies%node_body(node) /= b) then
        call fail(status, who//'node '//itoa(model%nodes%id(node))//' belongs to two rigid '// &
            'bodies, the '//body_name(bodies, bodies%node_body(node))//' and the '// &
            body_name(bodies, b)//' (merge rigid parts with *CONSTRAINED_RIGID_BODIES; a node '// &
            'is in one rigid body)')
        joined = .false.
        return
      end if
      bodies%node_body(node) = b
      if (.not. seen(b)) body_origin(:, b) = model%nodes%x(:, node)
      seen(b) = .true.
    end function joined

    !> The part at the head of p's chain of merges.
    integer function head(p)
      integer, intent(in) :: p              !< part index
      head = p
      do while (lead(head) /= head)
        head = lead(head)
      end do
    end function head

    !> Mass, first and second moments of every body about origin(:, b).
    subroutine sum_moments(origin_of)
      real(wp), intent(in) :: origin_of(:,:)      !< (3, n) origin per body
      body_mass = 0.0_wp
      body_first = 0.0_wp
      body_second = 0.0_wp
      do e = 1, model%elements%n
        b = bodies%body_of_part(model%elements%part(e))
        if (b == 0) cycle
        origin = origin_of(:, b)
        call element_moments(model, e, origin, mass, first, second)
        body_mass(b) = body_mass(b) + mass
        body_first(:, b) = body_first(:, b) + first
        body_second(:, :, b) = body_second(:, :, b) + second
      end do
      do node = 1, model%nodes%n
        b = bodies%node_body(node)
        if (b == 0) cycle
        if (merged_mass(node) == 0.0_wp) cycle
        origin = model%nodes%x(:, node) - origin_of(:, b)
        body_mass(b) = body_mass(b) + merged_mass(node)
        body_first(:, b) = body_first(:, b) + merged_mass(node)*origin
        body_second(:, :, b) = body_second(:, :, b) + merged_mass(node)*outer(origin, origin)
      end do
    end subroutine sum_moments

  end subroutine rigid_bodies_build

  !> "rigid body of part 3" or "nodal rigid body 7" (by the body's number), for messages.
  function body_name(bodies, b) result(name)
    type(rigid_bodies_t), intent(in) :: bodies    !< the bodies
    integer, intent(in) :: b                      !< body
    character(len=:), allocatable :: name
    if (bodies%body(b)%part > 0) then
      name = 'rigid body of part '//itoa(bodies%body(b)%id)
    else
      name = 'nodal rigid body '//itoa(bodies%body(b)%id)
    end if
  end function body_name

  !> The inertia tensor has no inertia about some axis (small_solve's test).
  pure logical function singular_inertia(inertia)
    real(wp), intent(in) :: inertia(3, 3)         !< inertia tensor
    real(wp) :: a(3, 3), x(3)
    a = inertia
    x = 0.0_wp
    call small_solve(3, a, x, singular_inertia)
    singular_inertia = .not. singular_inertia
  end function singular_inertia

  !> Mass, first moment and second moment (sum m r r^T) of element e about origin: solids
  !> as tetrahedra, shells as triangles of thickness T1 (3D: plate with its through-thickness
  !> term rho A t^3/12 n n^T) or of unit thickness (2D).
  subroutine element_moments(model, e, origin, mass, first, second)
    type(model_t), intent(in) :: model            !< resolved model
    integer, intent(in) :: e                      !< element
    real(wp), intent(in) :: origin(3)             !< reference point
    real(wp), intent(out) :: mass, first(3), second(3, 3)   !< moments
    real(wp) :: xe(3, 8), rho, thickness, y(3, 4), measure, normal(3), sm, s(3), area_vector(3)
    integer :: nn, i, k, p
    p = model%elements%part(e)
    rho = model%materials(model%parts(p)%material)%density
    nn = count(model%elements%conn(:, e) > 0)
    do i = 1, nn
      xe(:, i) = model%nodes%x(:, model%elements%conn(i, e)) - origin
    end do
    mass = 0.0_wp
    first = 0.0_wp
    second = 0.0_wp
    select case (model%elements%topology(e))
    case (TOPO_TRI3, TOPO_QUAD4)
      thickness = 1.0_wp
      if (model%dimension == 3) thickness = model%sections(model%parts(p)%section)%thickness(1)
      do k = 1, merge(1, 2, model%elements%topology(e) == TOPO_TRI3)
        y(:, 1:3) = xe(:, QUAD_TRIANGLES(:, k))
        area_vector = 0.5_wp*cross(y(:, 2) - y(:, 1), y(:, 3) - y(:, 1))
        measure = norm2(area_vector)
        if (measure == 0.0_wp) cycle
        normal = area_vector/measure
        sm = rho*thickness*measure
        call add_simplex(sm, y(:, 1:3))
        if (model%dimension == 3) second = second + sm*thickness**2/12.0_wp*outer(normal, normal)
      end do
    case (TOPO_TET4)
      call add_tet(xe(:, 1:4))
    case (TOPO_PENTA6)
      do k = 1, size(PENTA_TETS, 2)
        call add_tet(xe(:, PENTA_TETS(:, k)))
      end do
    case (TOPO_HEX8)
      do k = 1, size(HEX_TETS, 2)
        call add_tet(xe(:, HEX_TETS(:, k)))
      end do
    end select

  contains

    !> A tetrahedron of density rho.
    subroutine add_tet(corners)
      real(wp), intent(in) :: corners(3, 4)      !< corner coordinates
      measure = abs(dot_product(cross(corners(:, 2) - corners(:, 1), corners(:, 3) - &
                                      corners(:, 1)), corners(:, 4) - corners(:, 1)))/6.0_wp
      call add_simplex(rho*measure, corners)
    end subroutine add_tet

    !> A uniform simplex of mass sm: exact first moment sm*centroid and second moment
    !> sm/((d+1)(d+2)) (sum y_i y_i^T + s s^T), s = sum y_i, d = 2 (triangle) or 3.
    subroutine add_simplex(simplex_mass, corners)
      real(wp), intent(in) :: simplex_mass       !< its mass
      real(wp), intent(in) :: corners(:,:)       !< (3, d+1) corner coordinates
      integer :: nv, a
      nv = size(corners, 2)
      s = sum(corners, dim=2)
      mass = mass + simplex_mass
      first = first + simplex_mass*s/real(nv, wp)
      do a = 1, nv
        second = second + simplex_mass/real(nv*(nv + 1), wp)*outer(corners(:, a), corners(:, a))
      end do
      second = second + simplex_mass/real(nv*(nv + 1), wp)*outer(s, s)
    end subroutine add_simplex

  end subroutine element_moments

  !> Prescribed motions on rigid parts: DOF and VAD this module takes; every free degree of
  !> freedom (not held, not prescribed) of a body needs mass or inertia.
  subroutine check_motions(model, bodies, status)
    type(model_t), intent(in) :: model            !< resolved model
    type(rigid_bodies_t), intent(in) :: bodies    !< bodies built so far
    type(status_t), intent(inout) :: status       !< failure and why
    logical :: prescribed(6, bodies%n), free(3), along(2, bodies%n), exclusive(2, bodies%n)
    real(wp) :: vector(3, 2, bodies%n)
    integer :: k, b, slot, nfree, free_index(3), i, kind
    real(wp) :: block(3, 3), rhs(3)
    logical :: ok
    character(len=:), allocatable :: who
    prescribed = .false.
    along = .false.
    exclusive = .false.
    vector = 0.0_wp
    do k = 1, model%n_motions
      associate (pm => model%motions(k))
        if (pm%target_kind /= ON_PART .or. pm%target <= 0) cycle
        b = bodies%body_of_part(pm%target)
        if (b == 0) cycle
        who = '*BOUNDARY_PRESCRIBED_MOTION_RIGID on part '//itoa(model%parts(pm%target)%id)//': '
        slot = motion_slot(pm%dof)
        kind = vector_kind(pm%dof)
        if (kind > 0) then                            ! along / about the vector VID
          if (bodies%dim == 2 .and. (kind == 2 .or. abs(pm%direction(3)) > 0.0_wp)) then
            call fail(status, who//'DOF '//itoa(pm%dof)//' is not supported in 2D (4/-4 '// &
                'need a vector in the x-y plane; rotations: DOF 7)')
            return
          end if
          if (along(kind, b) .and. (any(vector(:, kind, b) /= pm%direction) .or. &
                                    exclusive(kind, b) .neqv. pm%dof < 0)) then
            call fail(status, who//'two motions along different vectors (DOF '// &
                itoa(pm%dof)//'): give one vector per body for translations and one for '// &
                'rotations')
            return
          end if
          along(kind, b) = .true.
          exclusive(kind, b) = pm%dof < 0
          vector(:, kind, b) = pm%direction
        else if (slot == 0 .or. (bodies%dim == 2 .and. (slot == 3 .or. slot == 4 .or. &
                                                        slot == 5))) then
          call fail(status, who//'DOF '//itoa(pm%dof)//' is not supported for rigid bodies '// &
              trim(merge('(2D: 1, 2, 4 and 7)   ', '(1-8, -4, -8)         ', bodies%dim == 2)))
          return
        end if
        if (pm%vad < VAD_VELOCITY .or. pm%vad > VAD_DISPLACEMENT) then
          call fail(status, who//'VAD '//itoa(pm%vad)//' is not supported (0 velocity, '// &
              '1 acceleration, 2 displacement)')
          return
        end if
        if (slot > 0) prescribed(slot, b) = .true.
      end associate
    end do
    do b = 1, bodies%n
      associate (body => bodies%body(b))
        who = body_name(bodies, b)
        ! a vector motion and the axes held or given: DOF 4/8 need the vector across the
        ! axes that are (it moves the body in the others); -4/-8 decide every component
        do kind = 1, 2
          if (.not. along(kind, b)) cycle
          if (kind == 1) then
            free = body%held_translation .or. prescribed(1:3, b)
          else
            free = body%held_rotation .or. prescribed(4:6, b)
          end if
          ok = .true.
          if (exclusive(kind, b)) then
            ok = .not. any(prescribed(3*kind-2:3*kind, b))
            if (ok) ok = all(.not. free .or. vector(:, kind, b) == 0.0_wp)
          else
            ok = all(.not. free .or. vector(:, kind, b) == 0.0_wp)
          end if
          if (.not. ok) then
            call fail(status, who//': the motion along its vector (DOF '// &
                trim(merge('4/-4', '8/-8', kind == 1))//') has a component along a '// &
                trim(merge('translation', 'rotation   ', kind == 1))//' that is held (CON1/'// &
                'CON2) or prescribed on its own: give the vector across those axes')
            return
          end if
          ! what the checks below see as given: every axis (-4, -8), or the axis of a vector
          ! along one
          if (exclusive(kind, b)) then
            prescribed(3*kind-2:3*kind, b) = .true.
          else if (count(vector(:, kind, b) /= 0.0_wp) == 1) then
            where (vector(:, kind, b) /= 0.0_wp) prescribed(3*kind-2:3*kind, b) = .true.
          end if
        end do
        if (body%mass <= 0.0_wp .and. any(.not. (body%held_translation .or. &
                                                 prescribed(1:3, b)))) then
          call fail(status, who//' has no mass but a free translation (give its shells '// &
              'a thickness T1, or hold or prescribe the translations)')
          return
        end if
        call note_free_directions(body, prescribed(:, b), bodies%dim, who)
        free = .not. (body%held_rotation .or. prescribed(4:6, b))
        nfree = 0
        do i = 1, 3
          if (.not. free(i)) cycle
          nfree = nfree + 1
          free_index(nfree) = i
        end do
        if (nfree == 0) cycle
        block(1:nfree, 1:nfree) = body%inertia0(free_index(1:nfree), free_index(1:nfree))
        rhs = 0.0_wp
        call small_solve(nfree, block(1:nfree, 1:nfree), rhs(1:nfree), ok)
        if (.not. ok) then
          call fail(status, who//' has no rotational inertia about a free axis (hold or '// &
              'prescribe its rotations)')
          return
        end if
      end associate
    end do
  end subroutine check_motions

  !> A body moved by a prescribed motion but free in other directions (not held by CMO/CON1/
  !> CON2, not prescribed): say so on the run log, since contact may move it there (a
  !> frictionless tool pressed on a bulging surface slides off sideways, as it would in
  !> LS-DYNA); a guided tool holds them with CMO = 1, CON1, CON2.
  subroutine note_free_directions(body, prescribed, dim, who)
    type(rigid_body_t), intent(in) :: body        !< the body
    logical, intent(in) :: prescribed(6)          !< translations x y z, rotations x y z
    integer, intent(in) :: dim                    !< 2 or 3
    character(len=*), intent(in) :: who           !< 'rigid part P'
    character(len=2), parameter :: NAMES(6) = ['x ', 'y ', 'z ', 'rx', 'ry', 'rz']
    logical :: free(6), exists(6)
    character(len=:), allocatable :: moved, loose
    integer :: i
    exists = .true.
    if (dim == 2) exists = [.true., .true., .false., .false., .false., .true.]
    free = exists .and. .not. ([body%held_translation, body%held_rotation] .or. prescribed)
    if (.not. (any(prescribed .and. exists) .and. any(free))) return
    moved = ''
    loose = ''
    do i = 1, 6
      if (prescribed(i) .and. exists(i)) moved = moved//' '//trim(NAMES(i))
      if (free(i)) loose = loose//' '//trim(NAMES(i))
    end do
    call say('note: '//who//' is moved along'//moved//' and free in'//loose//' (neither '// &
             'prescribed nor held by CMO/CON1/CON2): contact forces can move it there; '// &
             'CMO = 1 with CON1/CON2 holds a guided tool')
  end subroutine note_free_directions

  ! ------------------------------------------------------------------ state

  !> Initial velocity of body b: centre velocity v and angular velocity omega (3-vectors;
  !> components held by CON1/CON2 or absent in 2D are set to zero). Sets L = I omega.
  subroutine rigid_bodies_set_velocity(bodies, b, v, omega)
    type(rigid_bodies_t), intent(inout) :: bodies !< the bodies
    integer, intent(in) :: b                      !< body
    real(wp), intent(in) :: v(3), omega(3)        !< velocity of the centre, angular velocity
    real(wp) :: inertia(3, 3)
    associate (body => bodies%body(b))
      body%velocity = merge(0.0_wp, v, body%held_translation)
      body%omega = merge(0.0_wp, omega, body%held_rotation)
      inertia = spatial_inertia(body, body%rotation)
      body%angular_momentum = matmul(inertia, body%omega)
    end associate
  end subroutine rigid_bodies_set_velocity

  !> The rigid velocity field v = v_c + omega x (x - c) nearest to nodal velocities in the
  !> weighted least-squares sense (exact when they are a rigid field, as
  !> *INITIAL_VELOCITY_GENERATION's spin gives): about the nodes' mass centroid c_m the fit
  !> decouples, v_m = sum m v/M and J omega = sum m r x v with J = sum m (|r|^2 I - r r^T);
  !> then v_c = v_m + omega x (c - c_m) at the body's centre c. A direction J cannot resolve
  !> (nodes on a line, one node) gets no spin about it (J regularised by 1e-12 tr J).
  subroutine rigid_body_velocity_fit(centre, x, v, m, v_c, omega)
    real(wp), intent(in) :: centre(3)              !< the body's centre of mass
    real(wp), intent(in) :: x(:,:), v(:,:)         !< (3, n) node positions, velocities
    real(wp), intent(in) :: m(:)                   !< (n) node weights (masses)
    real(wp), intent(out) :: v_c(3), omega(3)      !< velocity at the centre, spin
    !> relative regularisation of the nodes' inertia (directions it cannot resolve)
    real(wp), parameter :: INERTIA_FLOOR = 1.0e-12_wp
    real(wp) :: mass, c_m(3), v_m(3), r(3), j(3, 3), j_inverse(3, 3), moment(3), det
    integer :: k, a
    mass = sum(m)
    v_c = 0.0_wp
    omega = 0.0_wp
    if (.not. mass > 0.0_wp) return
    c_m = matmul(x, m)/mass
    v_m = matmul(v, m)/mass
    j = 0.0_wp
    moment = 0.0_wp
    do k = 1, size(m)
      r = x(:, k) - c_m
      moment = moment + m(k)*cross(r, v(:, k) - v_m)   ! (exactly 0 for a uniform v)
      do a = 1, 3
        j(:, a) = j(:, a) - m(k)*r*r(a)
        j(a, a) = j(a, a) + m(k)*dot_product(r, r)
      end do
    end do
    if (j(1, 1) + j(2, 2) + j(3, 3) > 0.0_wp) then
      do a = 1, 3
        j(a, a) = j(a, a) + INERTIA_FLOOR*(j(1, 1) + j(2, 2) + j(3, 3))
      end do
      det = determinant(j)
      if (det > 0.0_wp) then
        call inverse(j, j_inverse)
        omega = matmul(j_inverse, moment)
      end if
    end if
    v_c = v_m + cross(omega, centre - c_m)
  end subroutine rigid_body_velocity_fit

  !> Add the force f at the point x_current (current position, dim components) of body b to
  !> its resultant force and moment about its current centre. force_sum and moment_sum are
  !> (3, n); the caller zeroes them before the first node.
  subroutine rigid_bodies_accumulate(bodies, b, x_current, f, force_sum, moment_sum)
    type(rigid_bodies_t), intent(in) :: bodies    !< the bodies
    integer, intent(in) :: b                      !< body
    real(wp), intent(in) :: x_current(:), f(:)    !< (dim) position and force
    real(wp), intent(inout) :: force_sum(:,:), moment_sum(:,:)   !< (3, n) resultants
    real(wp) :: r(3), f3(3)
    integer :: dim
    dim = size(f)
    r = 0.0_wp
    f3 = 0.0_wp
    r(1:dim) = x_current(1:dim) - bodies%body(b)%centre(1:dim)
    f3(1:dim) = f(1:dim)
    force_sum(:, b) = force_sum(:, b) + f3
    moment_sum(:, b) = moment_sum(:, b) + cross(r, f3)
  end subroutine rigid_bodies_accumulate

  !> One central-difference step of every body from t^n = t_new - dt_new: velocities at
  !> t_half = t^{n+1/2}, positions at t_new. force_sum/moment_sum: resultants at t^n (moment
  !> about the centre at t^n), summed over ranks. dt_avg = t^{n+1/2} - t^{n-1/2} (dt/2 in
  !> the first step). Sets the reactions and adds their work.
  subroutine rigid_bodies_advance(model, bodies, t_half, t_new, dt_avg, dt_new, force_sum, &
                                  moment_sum)
    type(model_t), intent(in) :: model            !< resolved model (motions, curves)
    type(rigid_bodies_t), intent(inout) :: bodies !< the bodies
    real(wp), intent(in) :: t_half, t_new         !< t^{n+1/2}, t^{n+1}
    real(wp), intent(in) :: dt_avg, dt_new        !< t^{n+1/2} - t^{n-1/2}, t^{n+1} - t^n
    real(wp), intent(in) :: force_sum(:,:), moment_sum(:,:)   !< (3, n) at t^n
    real(wp) :: rate(8), v_old(3), omega_old(3), l_old(3), l_pred(3), i_mid(3, 3)
    real(wp) :: r_mid(3, 3), omega_new(3), rate_old(6), vectors(3, 2), full(3), n(3)
    logical :: given(8), held_rot(3), exclusive(2)
    integer :: b, i, pass
    do b = 1, bodies%n
      associate (body => bodies%body(b))
        v_old = body%velocity
        omega_old = body%omega
        l_old = body%angular_momentum
        rate_old = [v_old, omega_old]
        call prescribed_rates(model, bodies, b, t_new - dt_new, t_half, t_new, dt_avg, &
                              dt_new, rate_old, rate, given, vectors, exclusive)
        ! translation (along a vector n, DOF 4: the component along n replaced; -4: v = r n)
        do i = 1, 3
          if (body%held_translation(i)) then
            body%velocity(i) = 0.0_wp
          else if (given(i)) then
            body%velocity(i) = rate(i)
          else if (body%mass > 0.0_wp) then
            body%velocity(i) = v_old(i) + dt_avg*force_sum(i, b)/body%mass
          end if
        end do
        n = vectors(:, 1)
        if (given(7)) then
          if (exclusive(1)) then
            body%velocity = rate(7)*n
          else
            body%velocity = body%velocity + (rate(7) - dot_product(body%velocity, n))*n
          end if
        end if
        body%reaction_force = 0.0_wp
        if (dt_avg > 0.0_wp) then
          full = body%mass*(body%velocity - v_old)/dt_avg - force_sum(:, b)
          where (body%held_translation .or. given(1:3)) body%reaction_force = full
          if (given(7)) then
            if (exclusive(1)) then
              body%reaction_force = full
            else
              body%reaction_force = body%reaction_force + dot_product(full, n)*n
            end if
          end if
        end if
        ! rotation: L predicted; omega from the mid-step inertia with held components
        l_pred = l_old + dt_avg*moment_sum(:, b)
        held_rot = body%held_rotation .or. given(4:6)
        omega_new = merge(0.0_wp, omega_old, body%held_rotation)
        where (given(4:6) .and. .not. body%held_rotation) omega_new = rate(4:6)
        n = vectors(:, 2)
        if (given(8) .and. exclusive(2)) then
          held_rot = .true.
          omega_new = rate(8)*n
        end if
        r_mid = body%rotation
        do pass = 0, MIDPOINT_CORRECTIONS
          if (pass > 0) r_mid = matmul(rodrigues(0.5_wp*dt_new*omega_new), body%rotation)
          i_mid = spatial_inertia(body, r_mid)
          if (given(8) .and. .not. exclusive(2)) then
            call solve_rotation_about(i_mid, l_pred, held_rot, n, rate(8), omega_new)
          else
            call solve_free_rotation(i_mid, l_pred, held_rot, omega_new)
          end if
        end do
        body%omega = omega_new
        body%angular_momentum = matmul(i_mid, omega_new)
        body%reaction_moment = 0.0_wp
        if (given(8) .and. .not. exclusive(2)) then
          ! about a vector n (DOF 8): the reaction lies in the held axes and along n
          if (dt_avg > 0.0_wp) body%reaction_moment = (body%angular_momentum - l_pred)/dt_avg
        else
          where (.not. held_rot) body%angular_momentum = l_pred   ! exactly, not to round-off
          if (dt_avg > 0.0_wp) then
            where (held_rot) body%reaction_moment = (body%angular_momentum - l_pred)/dt_avg
          end if
        end if
        body%reaction_work = body%reaction_work + dt_avg*0.5_wp* &
            (dot_product(body%reaction_force, v_old + body%velocity) + &
             dot_product(body%reaction_moment, omega_old + body%omega))
        ! positions at t^{n+1}
        body%centre_old = body%centre
        body%rotation_old = body%rotation
        body%centre = body%centre + dt_new*body%velocity
        body%rotation = orthonormalized(matmul(rodrigues(dt_new*body%omega), body%rotation))
        body%angle = body%angle + dt_new*body%omega
        body%dt_last = dt_new
      end associate
    end do
  end subroutine rigid_bodies_advance

  !> Prescribed velocities of body b for the step (slots 1-3 v, 4-6 omega) from its active
  !> motions (birth <= t_half <= death), in deck order (a later motion on the same DOF wins):
  !> VAD 0 v = curve(t_half); VAD 1 v = v^{n-1/2} + dt_avg curve(t_old); VAD 2
  !> v = (curve(t_new) - d^n)/dt_new with d^n the centre displacement (or angle) at t^n.
  !> Slots 7 and 8 hold the rates along and about the vectors (DOF 4/-4, 8/-8; vectors(:, 1)
  !> and (:, 2), exclusive for -4/-8: the other components are 0).
  subroutine prescribed_rates(model, bodies, b, t_old, t_half, t_new, dt_avg, dt_new, &
                              rate_old, rate, given, vectors, exclusive)
    type(model_t), intent(in) :: model            !< resolved model
    type(rigid_bodies_t), intent(in) :: bodies    !< the bodies
    integer, intent(in) :: b                      !< body
    real(wp), intent(in) :: t_old, t_half, t_new, dt_avg, dt_new   !< step times
    real(wp), intent(in) :: rate_old(6)           !< (v, omega) at t^{n-1/2}
    real(wp), intent(out) :: rate(8)              !< prescribed (v, omega, along, about)
    logical, intent(out) :: given(8)              !< the slot is prescribed
    real(wp), intent(out) :: vectors(3, 2)        !< unit vectors of slots 7 and 8
    logical, intent(out) :: exclusive(2)          !< -4, -8: only along / about the vector
    integer :: k, slot, kind
    real(wp) :: done, old
    rate = 0.0_wp
    given = .false.
    vectors = 0.0_wp
    exclusive = .false.
    do k = 1, model%n_motions
      associate (pm => model%motions(k))
        if (pm%target_kind /= ON_PART .or. pm%target <= 0) cycle
        if (bodies%body_of_part(pm%target) /= b) cycle
        if (t_half < pm%birth .or. t_half > pm%death) cycle
        slot = motion_slot(pm%dof)
        kind = vector_kind(pm%dof)
        if (kind > 0) then
          slot = 6 + kind
          vectors(:, kind) = pm%direction
          exclusive(kind) = pm%dof < 0
        end if
        if (slot == 0) cycle
        select case (pm%vad)
        case (VAD_VELOCITY)
          rate(slot) = pm%scale*curve_value(model%curves(pm%curve), t_half)
        case (VAD_ACCELERATION)
          if (kind > 0) then
            old = dot_product(rate_old(3*kind-2:3*kind), pm%direction)
          else
            old = rate_old(slot)
          end if
          rate(slot) = old + dt_avg*pm%scale*curve_value(model%curves(pm%curve), t_old)
        case (VAD_DISPLACEMENT)
          if (dt_new <= 0.0_wp) cycle
          if (kind == 1) then
            done = dot_product(bodies%body(b)%centre - bodies%body(b)%centre0, pm%direction)
          else if (kind == 2) then
            done = dot_product(bodies%body(b)%angle, pm%direction)
          else if (slot <= 3) then
            done = bodies%body(b)%centre(slot) - bodies%body(b)%centre0(slot)
          else
            done = bodies%body(b)%angle(slot - 3)
          end if
          rate(slot) = (pm%scale*curve_value(model%curves(pm%curve), t_new) - done)/dt_new
        case default
          cycle
        end select
        given(slot) = .true.
      end associate
    end do
  end subroutine prescribed_rates

  !> Displacement at t^{n+1} and velocity at t^{n+1/2} of the point of body b whose reference
  !> position is x0 (dim components): u = x_c + R (x0 - x_c0) - x0; v is the secant velocity
  !> (x^{n+1} - x^n)/dt of the last advance (so u^{n+1} = u^n + dt v holds for rigid nodes
  !> too), v_c + omega x (x - x_c) before the first advance.
  subroutine rigid_body_point_motion(bodies, b, x0, u, v)
    type(rigid_bodies_t), intent(in) :: bodies    !< the bodies
    integer, intent(in) :: b                      !< body
    real(wp), intent(in) :: x0(:)                 !< (dim) reference position
    real(wp), intent(out) :: u(:), v(:)           !< (dim) displacement, velocity
    real(wp) :: r0(3), x_new(3), x_old(3), v3(3)
    integer :: dim
    dim = size(x0)
    associate (body => bodies%body(b))
      r0 = 0.0_wp
      r0(1:dim) = x0(1:dim) - body%centre0(1:dim)
      x_new = body%centre + matmul(body%rotation, r0)
      if (body%dt_last > 0.0_wp) then
        x_old = body%centre_old + matmul(body%rotation_old, r0)
        v3 = (x_new - x_old)/body%dt_last
      else
        v3 = body%velocity + cross(body%omega, x_new - body%centre)
      end if
      u(1:dim) = x_new(1:dim) - x0(1:dim)
      v(1:dim) = v3(1:dim)
    end associate
  end subroutine rigid_body_point_motion

  !> Kinetic energy of all bodies with the half-step velocities: sum of m v.v/2 + omega.L/2.
  pure real(wp) function rigid_bodies_kinetic_energy(bodies) result(energy)
    type(rigid_bodies_t), intent(in) :: bodies    !< the bodies
    integer :: b
    energy = 0.0_wp
    do b = 1, bodies%n
      associate (body => bodies%body(b))
        energy = energy + 0.5_wp*body%mass*dot_product(body%velocity, body%velocity) + &
                 0.5_wp*dot_product(body%omega, body%angular_momentum)
      end associate
    end do
  end function rigid_bodies_kinetic_energy

  !> Reaction force and moment (about the centre) of body b in its last advance: what the
  !> constraints and prescribed motions added to the applied load, at t^n.
  subroutine rigid_body_reaction(bodies, b, force, moment)
    type(rigid_bodies_t), intent(in) :: bodies    !< the bodies
    integer, intent(in) :: b                      !< body
    real(wp), intent(out) :: force(3), moment(3)  !< reaction force and moment
    force = bodies%body(b)%reaction_force
    moment = bodies%body(b)%reaction_moment
  end subroutine rigid_body_reaction

  ! ------------------------------------------------------------------ helpers

  !> Slot of a DOF in (v, omega): 1-3 -> 1-3, 5-7 -> 4-6, others 0.
  pure integer function motion_slot(dof)
    integer, intent(in) :: dof                    !< DOF code
    select case (dof)
    case (1:3)
      motion_slot = dof
    case (5:7)
      motion_slot = dof - ROTATION_DOF_SHIFT
    case default
      motion_slot = 0
    end select
  end function motion_slot

  !> A motion along a vector (DOF 4, -4): 1; about a vector (8, -8): 2; else 0.
  pure integer function vector_kind(dof)
    integer, intent(in) :: dof                    !< DOF code
    select case (dof)
    case (4, -4)
      vector_kind = 1
    case (8, -8)
      vector_kind = 2
    case default
      vector_kind = 0
    end select
  end function vector_kind

  !> Spatial inertia R I_0 R^T of a body at rotation r.
  pure function spatial_inertia(body, r) result(inertia)
    type(rigid_body_t), intent(in) :: body        !< the body
    real(wp), intent(in) :: r(3, 3)               !< rotation
    real(wp) :: inertia(3, 3)
    inertia = matmul(r, matmul(body%inertia0, transpose(r)))
  end function spatial_inertia

  !> The components not held, in order (free_index(1:nfree)).
  pure subroutine free_components(held, free_index, nfree)
    logical, intent(in) :: held(3)                !< components given
    integer, intent(out) :: free_index(3)         !< the free ones
    integer, intent(out) :: nfree                 !< how many
    integer :: i
    nfree = 0
    free_index = 0
    do i = 1, 3
      if (held(i)) cycle
      nfree = nfree + 1
      free_index(nfree) = i
    end do
  end subroutine free_components

  !> omega with its held components kept: the free ones solve the free rows of
  !> inertia omega = l. A singular free block (excluded by rigid_bodies_build) keeps them.
  subroutine solve_free_rotation(inertia, l, held, omega)
    real(wp), intent(in) :: inertia(3, 3), l(3)   !< spatial inertia, angular momentum
    logical, intent(in) :: held(3)                !< components given
    real(wp), intent(inout) :: omega(3)           !< held components in, free ones out
    integer :: free_index(3), nfree, i
    real(wp) :: block(3, 3), rhs(3)
    logical :: ok
    call free_components(held, free_index, nfree)
    if (nfree == 0) return
    block(1:nfree, 1:nfree) = inertia(free_index(1:nfree), free_index(1:nfree))
    rhs(1:nfree) = l(free_index(1:nfree))
    do i = 1, 3
      if (held(i)) rhs(1:nfree) = rhs(1:nfree) - inertia(free_index(1:nfree), i)*omega(i)
    end do
    call small_solve(nfree, block(1:nfree, 1:nfree), rhs(1:nfree), ok)
    if (ok) omega(free_index(1:nfree)) = rhs(1:nfree)
  end subroutine solve_free_rotation

  !> omega with its held components kept and omega . n = r (a rotation about the unit vector
  !> n, DOF 8, n across the held axes): inertia omega = l + lambda n + (moments on the held
  !> axes), solved as the bordered system of the free components and lambda.
  subroutine solve_rotation_about(inertia, l, held, n, r, omega)
    real(wp), intent(in) :: inertia(3, 3), l(3)   !< spatial inertia, angular momentum
    logical, intent(in) :: held(3)                !< components given
    real(wp), intent(in) :: n(3), r               !< the vector and the rate about it
    real(wp), intent(inout) :: omega(3)           !< held components in, the others out
    integer :: free_index(3), nfree, i
    real(wp) :: block(4, 4), rhs(4), s
    logical :: ok
    call free_components(held, free_index, nfree)
    if (nfree == 0) return
    ! rows: the free rows of I omega - lambda n = l; last: n . omega = r (the border scaled
    ! by the inertia's size, s: the pivots stay comparable)
    s = maxval([(abs(inertia(i, i)), i = 1, 3)])
    block = 0.0_wp
    block(1:nfree, 1:nfree) = inertia(free_index(1:nfree), free_index(1:nfree))
    block(1:nfree, nfree + 1) = -s*n(free_index(1:nfree))
    block(nfree + 1, 1:nfree) = s*n(free_index(1:nfree))
    rhs(1:nfree) = l(free_index(1:nfree))
    rhs(nfree + 1) = s*r
    do i = 1, 3
      if (.not. held(i)) cycle
      rhs(1:nfree) = rhs(1:nfree) - inertia(free_index(1:nfree), i)*omega(i)
      rhs(nfree + 1) = rhs(nfree + 1) - s*n(i)*omega(i)
    end do
    call small_solve(nfree + 1, block(1:nfree + 1, 1:nfree + 1), rhs(1:nfree + 1), ok)
    if (ok) omega(free_index(1:nfree)) = rhs(1:nfree)
  end subroutine solve_rotation_about

  !> Solve a x = b (n <= 4) by Gaussian elimination with partial pivoting; b is replaced by
  !> x. ok is false when a pivot is below SINGULAR_PIVOT times the largest diagonal entry.
  pure subroutine small_solve(n, a, b, ok)
    integer, intent(in) :: n                      !< order
    real(wp), intent(inout) :: a(n, n), b(n)      !< matrix (destroyed), right side -> x
    logical, intent(out) :: ok                    !< not singular
    integer :: k, i, p
    real(wp) :: scale, factor, row(n), tmp
    scale = maxval([(abs(a(i, i)), i = 1, n)])
    ok = scale > 0.0_wp
    if (.not. ok) return
    do k = 1, n
      p = k - 1 + maxloc(abs(a(k:n, k)), dim=1)
      if (abs(a(p, k)) <= SINGULAR_PIVOT*scale) then
        ok = .false.
        return
      end if
      if (p /= k) then
        row = a(k, :)
        a(k, :) = a(p, :)
        a(p, :) = row
        tmp = b(k)
        b(k) = b(p)
        b(p) = tmp
      end if
      do i = k + 1, n
        factor = a(i, k)/a(k, k)
        a(i, k:n) = a(i, k:n) - factor*a(k, k:n)
        b(i) = b(i) - factor*b(k)
      end do
    end do
    do k = n, 1, -1
      b(k) = (b(k) - dot_product(a(k, k+1:n), b(k+1:n)))/a(k, k)
    end do
  end subroutine small_solve

  !> Rotation matrix exp([w]x) of the rotation vector w (Rodrigues' formula).
  pure function rodrigues(w) result(r)
    real(wp), intent(in) :: w(3)                  !< rotation vector (axis times angle)
    real(wp) :: r(3, 3)
    real(wp) :: theta, a, c, k(3, 3)
    theta = norm2(w)
    if (theta < SMALL_ANGLE) then
      a = 1.0_wp - theta**2/6.0_wp + theta**4/120.0_wp          ! sin(theta)/theta
      c = 0.5_wp - theta**2/24.0_wp + theta**4/720.0_wp         ! (1 - cos(theta))/theta^2
    else
      a = sin(theta)/theta
      c = (1.0_wp - cos(theta))/theta**2
    end if
    k = reshape([0.0_wp, w(3), -w(2), -w(3), 0.0_wp, w(1), w(2), -w(1), 0.0_wp], [3, 3])
    r = IDENTITY + a*k + c*matmul(k, k)
  end function rodrigues

  !> The rotation nearest to r after round-off: Gram-Schmidt on its columns.
  pure function orthonormalized(r) result(q)
    real(wp), intent(in) :: r(3, 3)               !< nearly orthogonal matrix
    real(wp) :: q(3, 3)
    q(:, 1) = r(:, 1)/norm2(r(:, 1))
    q(:, 2) = r(:, 2) - dot_product(q(:, 1), r(:, 2))*q(:, 1)
    q(:, 2) = q(:, 2)/norm2(q(:, 2))
    q(:, 3) = cross(q(:, 1), q(:, 2))
  end function orthonormalized

  !> Outer product a b^T of 3-vectors.
  pure function outer(a, b) result(m)
    real(wp), intent(in) :: a(3), b(3)            !< vectors
    real(wp) :: m(3, 3)
    integer :: j
    do j = 1, 3
      m(:, j) = a*b(j)
    end do
  end function outer

  !> Record a failure.
  subroutine fail(status, message)
    type(status_t), intent(inout) :: status       !< status set
    character(len=*), intent(in) :: message      !< what and where
    status%ok = .false.
    status%message = message
  end subroutine fail

end module mefem_rigid_bodies
