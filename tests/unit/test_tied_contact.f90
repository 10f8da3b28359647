!> Tied contact weights (mefem_tied_contact): a block of 3^3 cubes of Kuhn tetrahedra (SURFB)
!> under a block of 4^3 (SURFA), both with their interface nodes moved at random in the plane
!> of the interface (non-matching, irregular meshes). Every SURFA interface node is tied by
!> dual mortar weights, and the weights
!>  - sum to 1 and reproduce a linear field exactly (so a uniform strain crosses the tie),
!>  - carry the consistent nodal forces of a uniform traction on SURFA onto the consistent
!>    nodal forces of that traction on SURFB (sum_s w_sc int N_s = int N_c: the patch test);
!> the SURFA nodes off the interface stay untied; a node set with a node off the facets is
!> tied by projection (its barycentric coordinates); a tolerance (SST < 0) below the gap ties
!> nothing; a node tied by two contacts is an error that names both.
! ranks: 1
program test_tied_contact
  use mefem_kinds, only: wp
  use mefem_errors, only: status_t
  use mefem_model, only: model_t, set_t, contact_t, ELEM_SOLID, TOPO_TET4, SET_NODE, &
                         SURFACE_PART, SURFACE_NODE_SET
  use mefem_tied_contact, only: tied_nodes_t, tied_contact_build
  use mefem_testing, only: test_start, test_finish, check, check_close, check_equal
  implicit none

  real(wp), parameter :: TIGHT = 1.0e-13_wp        !< round-off of sums of O(100) terms
  integer, parameter :: N_LOWER = 3, N_UPPER = 4   !< cubes per edge
  real(wp), parameter :: JITTER = 0.15_wp          !< in-plane node shift / cube size
  !> Axis permutations of the six Kuhn tetrahedra of a cube.
  integer, parameter :: KUHN(3, 6) = reshape([1, 2, 3,  1, 3, 2,  2, 1, 3,  2, 3, 1,  3, 1, 2, &
                                              3, 2, 1], [3, 6])
  type(model_t) :: model
  integer :: n_lower_nodes

  call test_start('tied_contact')
  call two_blocks(model, n_lower_nodes)
  call test_dual_weights()
  call test_projection_and_tolerance()
  call test_tied_twice()
  call test_finish()

contains

  !> The lower block (part 1, z in [0, 1]) and the upper block (part 2, z in [1, 2]).
  subroutine two_blocks(model, n_lower_nodes)
    type(model_t), intent(out) :: model             !< the model
    integer, intent(out) :: n_lower_nodes           !< nodes of the lower block
    real(wp), allocatable :: x1(:,:), x2(:,:)
    integer, allocatable :: c1(:,:), c2(:,:)
    integer :: i
    call block(N_LOWER, 0.0_wp, 1, x1, c1)
    call block(N_UPPER, 1.0_wp, 7, x2, c2)
    n_lower_nodes = size(x1, 2)
    model%dimension = 3
    model%nodes%n = size(x1, 2) + size(x2, 2)
    model%nodes%x = reshape([x1, x2], [3, model%nodes%n])
    model%nodes%id = [(i, i = 1, model%nodes%n)]
    model%elements%n = size(c1, 2) + size(c2, 2)
    model%elements%id = [(i, i = 1, model%elements%n)]
    model%elements%part = [spread(1, 1, size(c1, 2)), spread(2, 1, size(c2, 2))]
    model%elements%part_id = model%elements%part
    model%elements%keyword = spread(ELEM_SOLID, 1, model%elements%n)
    model%elements%topology = spread(TOPO_TET4, 1, model%elements%n)
    allocate(model%elements%conn(8, model%elements%n))
    model%elements%conn = 0
    model%elements%conn(1:4, :) = reshape([c1, c2 + n_lower_nodes], [4, model%elements%n])
    model%n_parts = 2
    allocate(model%parts(2))
    model%parts(1)%id = 1
    model%parts(2)%id = 2
    allocate(model%sets(0))
  end subroutine two_blocks

  !> A unit cube of n^3 cubes of 6 tetrahedra at height z0; the nodes inside the faces
  !> x = 0, 1 and y = 0, 1 moved in x and y by up to JITTER of a cube (the interface planes
  !> z = 0 and z = 1 stay planes).
  subroutine block(n, z0, seed, x, conn)
    integer, intent(in) :: n, seed                  !< cubes per edge, random seed
    real(wp), intent(in) :: z0                      !< bottom height
    real(wp), allocatable, intent(out) :: x(:,:)    !< (3, (n+1)^3)
    integer, allocatable, intent(out) :: conn(:,:)  !< (4, 6 n^3)
    integer :: i, j, k, p, t, v, e, corner(3, 4), q(4)
    allocate(x(3, (n + 1)**3), conn(4, 6*n**3))
    do k = 0, n
      do j = 0, n
        do i = 0, n
          p = node(n, i, j, k)
          x(:, p) = [real(i, wp)/n, real(j, wp)/n, z0 + real(k, wp)/n]
          if (min(i, j) > 0 .and. max(i, j) < n) x(1:2, p) = x(1:2, p) + &
              JITTER/n*2.0_wp*([noise(seed*1000 + 2*p), noise(seed*1000 + 2*p + 1)] - 0.5_wp)
        end do
      end do
    end do
    e = 0
    do k = 0, n - 1
      do j = 0, n - 1
        do i = 0, n - 1
          do t = 1, 6
            corner(:, 1) = 0
            do v = 2, 4
              corner(:, v) = corner(:, v - 1)
              corner(KUHN(v - 1, t), v) = 1
            end do
            do v = 1, 4
              q(v) = node(n, i + corner(1, v), j + corner(2, v), k + corner(3, v))
            end do
            if (volume(x(:, q)) < 0.0_wp) q(2:3) = q(3:2:-1)
            e = e + 1
            conn(:, e) = q
          end do
        end do
      end do
    end do
  end subroutine block

  !> Tie SURFA = part 2 to SURFB = part 1.
  subroutine test_dual_weights()
    type(tied_nodes_t) :: tied
    type(status_t) :: status
    real(wp) :: a(3, 3), b(3), u_s(3), worst_linear, worst_sum, worst_force
    real(wp), allocatable :: area_a(:), area_b(:), carried(:)
    integer :: i, e, interface_nodes
    call set_ties(model, [tie(SURFACE_PART, 2, 0.0_wp)])
    call tied_contact_build(model, tied, status)
    call check(status%ok, 'dual: built', status%message)
    if (.not. status%ok) return
    interface_nodes = count(abs(model%nodes%x(3, n_lower_nodes + 1:) - 1.0_wp) < 1.0e-12_wp)
    call check_equal(tied%n, interface_nodes, 'dual: every SURFA node of the interface tied')
    call check(all(tied%dual), 'dual: all by dual mortar weights')
    call check(all(abs(model%nodes%x(3, tied%slave) - 1.0_wp) < 1.0e-12_wp), &
               'dual: only interface nodes tied')
    call check(all(tied%master <= n_lower_nodes), 'dual: the masters are SURFB nodes')
    ! linear reproduction and partition of unity
    a = reshape([0.3_wp, -1.1_wp, 0.7_wp, 2.0_wp, 0.1_wp, -0.4_wp, 0.9_wp, 0.5_wp, 1.3_wp], &
                [3, 3])
    b = [0.2_wp, -0.6_wp, 1.0_wp]
    worst_linear = 0.0_wp
    worst_sum = 0.0_wp
    do i = 1, tied%n
      u_s = 0.0_wp
      do e = tied%start(i), tied%start(i + 1) - 1
        u_s = u_s + tied%weight(e)*(matmul(a, model%nodes%x(:, tied%master(e))) + b)
      end do
      worst_linear = max(worst_linear, maxval(abs(u_s - (matmul(a, &
          model%nodes%x(:, tied%slave(i))) + b))))
      worst_sum = max(worst_sum, abs(sum(tied%weight(tied%start(i):tied%start(i + 1) - 1)) - &
                                     1.0_wp))
    end do
    call check(worst_sum < TIGHT, 'dual: weights sum to 1', real_text(worst_sum))
    call check(worst_linear < TIGHT, 'dual: a linear field reproduced exactly', &
               real_text(worst_linear))
    ! a uniform traction: the slave nodes' consistent forces, carried to the masters, are the
    ! masters' consistent forces
    call interface_areas(1, area_b)
    call interface_areas(2, area_a)
    allocate(carried(model%nodes%n))
    carried = 0.0_wp
    do i = 1, tied%n
      do e = tied%start(i), tied%start(i + 1) - 1
        carried(tied%master(e)) = carried(tied%master(e)) + tied%weight(e)*area_a(tied%slave(i))
      end do
    end do
    worst_force = maxval(abs(carried - area_b))
    call check(worst_force < TIGHT, 'dual: a uniform traction carried onto the master''s '// &
               'consistent forces (patch test)', real_text(worst_force))
    call check_close(sum(area_a), 1.0_wp, TIGHT, 'dual: SURFA interface area 1')
  end subroutine test_dual_weights

  !> A node set holding one free node (on no element) 0.01 above the lower block's top face:
  !> tied by projection; a tolerance below its height leaves it untied.
  subroutine test_projection_and_tolerance()
    type(tied_nodes_t) :: tied
    type(status_t) :: status
    type(model_t) :: lifted
    real(wp) :: p(3)
    integer :: s
    lifted = model
    ! an extra node above the lower block's top face, on no element
    p = [0.41_wp, 0.37_wp, 1.01_wp]
    lifted%nodes%n = model%nodes%n + 1
    lifted%nodes%x = reshape([model%nodes%x, p], [3, lifted%nodes%n])
    lifted%nodes%id = [model%nodes%id, 99999]
    s = add_node_set(lifted, 5, [lifted%nodes%n])
    call set_ties(lifted, [tie(SURFACE_NODE_SET, s, 0.0_wp)])
    call tied_contact_build(lifted, tied, status)
    call check(status%ok, 'projection: built', status%message)
    if (.not. status%ok) return
    call check_equal(tied%n, 1, 'projection: the free node tied')
    if (tied%n /= 1) return
    call check(.not. tied%dual(1), 'projection: by projection weights')
    call check_equal(tied%start(2) - tied%start(1), 3, 'projection: three masters')
    ! the weights are the barycentric coordinates of (x, y) on the master triangle
    call check(maxval(abs(sum(spread(tied%weight(1:3), 1, 2)* &
                              lifted%nodes%x(1:2, tied%master(1:3)), dim=2) - p(1:2))) < TIGHT, &
               'projection: the weights interpolate the projected point')
    call check(all(tied%weight(1:3) >= 0.0_wp), 'projection: inside the triangle')
    ! SST = -0.005: below the 0.01 gap, nothing tied
    call set_ties(lifted, [tie(SURFACE_NODE_SET, s, -0.005_wp)])
    call tied_contact_build(lifted, tied, status)
    call check(status%ok .and. tied%n == 0 .and. tied%untied(1) == 1 .and. &
               tied%first_untied(1) == lifted%nodes%n, &
               'projection: a tolerance below the gap ties nothing, the node reported')
  end subroutine test_projection_and_tolerance

  !> The same SURFA in two ties.
  subroutine test_tied_twice()
    type(tied_nodes_t) :: tied
    type(status_t) :: status
    call set_ties(model, [tie(SURFACE_PART, 2, 0.0_wp), tie(SURFACE_PART, 2, 0.0_wp)])
    model%ties(1)%id = 11
    model%ties(2)%id = 12
    call tied_contact_build(model, tied, status)
    call check(.not. status%ok .and. index(status%message, 'is tied by contact 11 and by '// &
               'contact 12') > 0, 'twice: an error naming both contacts', status%message)
  end subroutine test_tied_twice

  ! ------------------------------------------------------------------ helpers

  !> A tie of SURFA (kind, index) to SURFB = part 1 with SST.
  type(contact_t) function tie(kind, target, sst)
    integer, intent(in) :: kind, target             !< SURFATYP code, index
    real(wp), intent(in) :: sst                     !< SAST (SST)
    tie%tied = .true.
    tie%surf_a_type = kind
    tie%surf_a = target
    tie%surf_b_type = SURFACE_PART
    tie%surf_b = 1
    tie%sast = sst
  end function tie

  !> Replace the model's ties.
  subroutine set_ties(m, ties)
    type(model_t), intent(inout) :: m               !< the model
    type(contact_t), intent(in) :: ties(:)          !< the ties
    m%ties = ties
    m%n_ties = size(ties)
  end subroutine set_ties

  !> Append a node set (members: node indices); returns its index.
  integer function add_node_set(m, id, members)
    type(model_t), intent(inout) :: m               !< the model
    integer, intent(in) :: id, members(:)           !< set id, nodes
    type(set_t) :: set
    set%id = id
    set%kind = SET_NODE
    set%n = size(members)
    set%member_ids = members
    set%members = members
    m%sets = [m%sets, set]
    m%n_sets = m%n_sets + 1
    add_node_set = m%n_sets
  end function add_node_set

  !> int N_c over the plane z = 1 of part p's exterior faces: a third of each triangle's area
  !> at its corners.
  subroutine interface_areas(p, area)
    integer, intent(in) :: p                        !< part
    real(wp), allocatable, intent(out) :: area(:)   !< (nodes)
    integer, parameter :: FACES(3, 4) = reshape([1, 2, 3,  1, 2, 4,  2, 3, 4,  1, 3, 4], [3, 4])
    real(wp) :: xf(3, 3), t
    integer :: e, f, v
    allocate(area(model%nodes%n))
    area = 0.0_wp
    do e = 1, model%elements%n
      if (model%elements%part(e) /= p) cycle
      do f = 1, 4
        do v = 1, 3
          xf(:, v) = model%nodes%x(:, model%elements%conn(FACES(v, f), e))
        end do
        if (any(abs(xf(3, :) - 1.0_wp) > 1.0e-12_wp)) cycle
        t = 0.5_wp*abs((xf(1, 2) - xf(1, 1))*(xf(2, 3) - xf(2, 1)) - &
                       (xf(2, 2) - xf(2, 1))*(xf(1, 3) - xf(1, 1)))
        do v = 1, 3
          area(model%elements%conn(FACES(v, f), e)) = &
              area(model%elements%conn(FACES(v, f), e)) + t/3.0_wp
        end do
      end do
    end do
  end subroutine interface_areas

  pure integer function node(n, i, j, k)
    integer, intent(in) :: n, i, j, k               !< cubes per edge, grid point
    node = 1 + i + (n + 1)*(j + (n + 1)*k)
  end function node

  !> Signed volume of a tetrahedron.
  pure real(wp) function volume(xt)
    real(wp), intent(in) :: xt(3, 4)                !< corners
    real(wp) :: a(3), b(3), c(3)
    a = xt(:, 2) - xt(:, 1)
    b = xt(:, 3) - xt(:, 1)
    c = xt(:, 4) - xt(:, 1)
    volume = (a(1)*(b(2)*c(3) - b(3)*c(2)) + a(2)*(b(3)*c(1) - b(1)*c(3)) + &
              a(3)*(b(1)*c(2) - b(2)*c(1)))/6.0_wp
  end function volume

  !> Pseudo-random number in [0, 1) from an integer (deterministic, no state).
  pure real(wp) function noise(i)
    integer, intent(in) :: i                        !< seed
    real(wp) :: t
    t = sin(12.9898_wp*i + 4.1414_wp)*43758.5453_wp
    noise = t - floor(t)
  end function noise

  function real_text(v) result(s)
    real(wp), intent(in) :: v                       !< value
    character(len=24) :: s
    write(s, '(es12.4)') v
  end function real_text

end program test_tied_contact
