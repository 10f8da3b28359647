!> Contact surfaces and candidate search (mefem_contact_surfaces): exterior faces of a cube of
!> tetrahedra (count, area, outward normals), of two parts and of boxes of hexahedra and
!> wedges; segment sets given with flipped segments come out oriented outward; 2D boundary
!> edges of triangle and quadrilateral meshes (perimeter, outward); the hex box's quadrilaterals
!> as the weighted triangles of their two triangulations; 3D shells as facets; the
!> failures with their messages. Search: the pairs of a brute-force O(n m) reference on
!> irregular 3D and 2D surfaces (same set, same order), no pair missing whose vertices come
!> within the margin, reuse of the grid arrays, and timings for 50 000 slave facets.
! ranks: 1
program test_contact_surfaces
  use mefem_kinds, only: wp, i8
  use mefem_errors, only: status_t
  use mefem_model, only: model_t, set_t, contact_t, ELEM_SOLID, ELEM_SHELL, SET_SEGMENT, &
                         SET_PART, TOPO_TRI3, TOPO_QUAD4, TOPO_TET4, TOPO_PENTA6, TOPO_HEX8, &
                         SURFACE_SEGMENT_SET, SURFACE_PART_SET, SURFACE_PART
  use mefem_contact_surfaces, only: contact_surface_t, contact_search_t, &
                                    contact_surface_build, contact_surface_pair_build, &
                                    contact_facet_area_vector, contact_search_build, &
                                    contact_surface_triangulate
  use mefem_testing, only: test_start, test_finish, check, check_close, check_equal
  implicit none

  !> Round-off tolerances: sums of O(100) areas of order 1 (measured errors <= 4e-15).
  real(wp), parameter :: TIGHT = 1.0e-13_wp
  !> Hexahedron corners (output order) as offsets (x, y, z) from the lower corner.
  integer, parameter :: HEX_CORNER(3, 8) = reshape([0, 0, 0,  1, 0, 0,  1, 1, 0,  0, 1, 0, &
                                                    0, 0, 1,  1, 0, 1,  1, 1, 1,  0, 1, 1], &
                                                   [3, 8])
  !> Two wedges of a hexahedron (triangle 1-2-3 over 5-6-7, 1-3-4 over 5-7-8).
  integer, parameter :: HEX_WEDGES(6, 2) = reshape([1, 2, 3, 5, 6, 7,  1, 3, 4, 5, 7, 8], [6, 2])
  !> Axis permutations of the six Kuhn tetrahedra of a hexahedron.
  integer, parameter :: KUHN(3, 6) = reshape([1, 2, 3,  1, 3, 2,  2, 1, 3,  2, 3, 1,  3, 1, 2, &
                                              3, 2, 1], [3, 6])

  call test_start('contact_surfaces')
  call test_cube_of_tets()
  call test_two_parts()
  call test_hex_and_wedge_boxes()
  call test_flipped_segments_3d()
  call test_2d_boundary_edges()
  call test_shells_as_facets()
  call test_failures()
  call test_search_3d()
  call test_search_2d()
  call test_search_reuse()
  call test_search_sparse_master()
  call test_search_timing()
  call test_extraction_timing()
  call test_finish()

contains

  ! ------------------------------------------------------------------ models

  !> A model over the given nodes and elements, parts 1..n_parts (ids 10, 20, ...).
  subroutine make_model(model, dim, x, conn, topology, keyword, part, n_parts)
    type(model_t), intent(out) :: model          !< the model
    integer, intent(in) :: dim                   !< 2 or 3
    real(wp), intent(in) :: x(:,:)               !< (3, nnode) coordinates
    integer, intent(in) :: conn(:,:)             !< (nn, nel) corners, output order
    integer, intent(in) :: topology(:), keyword(:), part(:)  !< (nel) TOPO_*, ELEM_*, part
    integer, intent(in) :: n_parts               !< parts
    integer :: i, nel
    model%dimension = dim
    model%nodes%n = size(x, 2)
    model%nodes%x = x
    model%nodes%id = [(i, i = 1, size(x, 2))]
    nel = size(conn, 2)
    model%elements%n = nel
    model%elements%id = [(i, i = 1, nel)]
    model%elements%part = part
    model%elements%part_id = 10*part
    model%elements%keyword = keyword
    model%elements%topology = topology
    allocate(model%elements%conn(8, nel))
    model%elements%conn = 0
    model%elements%conn(1:size(conn, 1), :) = conn
    model%n_parts = n_parts
    allocate(model%parts(n_parts))
    do i = 1, n_parts
      model%parts(i)%id = 10*i
    end do
    allocate(model%sets(0))
  end subroutine make_model

  !> Append a set (members are indices; user ids = indices); returns its index.
  integer function add_set(model, kind, id, members, n)
    type(model_t), intent(inout) :: model        !< the model
    integer, intent(in) :: kind, id              !< SET_* kind and id
    integer, intent(in) :: members(:)            !< part indices or 4 nodes per segment
    integer, intent(in) :: n                     !< members (segments for a segment set)
    type(set_t) :: set
    set%id = id
    set%kind = kind
    set%n = n
    set%member_ids = members
    set%members = members
    model%sets = [model%sets, set]
    model%n_sets = model%n_sets + 1
    add_set = model%n_sets
  end function add_set

  !> Pseudo-random number in [0, 1) from an integer (deterministic, no state).
  pure real(wp) function noise(i)
    integer, intent(in) :: i   !< seed
    real(wp) :: t
    t = sin(12.9898_wp*i + 4.1414_wp)*43758.5453_wp
    noise = t - floor(t)
  end function noise

  !> Grid of (n+1)^3 nodes on the unit cube, interior nodes moved by up to jitter.
  subroutine cube_nodes(n, jitter, x)
    integer, intent(in) :: n                     !< cells per edge
    real(wp), intent(in) :: jitter               !< interior displacement amplitude
    real(wp), allocatable, intent(out) :: x(:,:) !< (3, (n+1)^3)
    integer :: i, j, k, p
    allocate(x(3, (n + 1)**3))
    do k = 0, n
      do j = 0, n
        do i = 0, n
          p = node_of(n, i, j, k)
          x(:, p) = [i, j, k]/real(n, wp)
          if (min(i, j, k) > 0 .and. max(i, j, k) < n) &
            x(:, p) = x(:, p) + jitter*([noise(3*p), noise(3*p + 1), noise(3*p + 2)] - 0.5_wp)
        end do
      end do
    end do
  end subroutine cube_nodes

  !> Node index of grid point (i, j, k) of an n^3 cube grid.
  pure integer function node_of(n, i, j, k)
    integer, intent(in) :: n, i, j, k   !< cells per edge, grid point
    node_of = 1 + i + (n + 1)*(j + (n + 1)*k)
  end function node_of

  !> Hexahedra of the n^3 cube grid, corners in output order.
  subroutine cube_hexes(n, conn)
    integer, intent(in) :: n                      !< cells per edge
    integer, allocatable, intent(out) :: conn(:,:)   !< (8, n^3)
    integer :: i, j, k, c, e
    allocate(conn(8, n**3))
    e = 0
    do k = 0, n - 1
      do j = 0, n - 1
        do i = 0, n - 1
          e = e + 1
          do c = 1, 8
            conn(c, e) = node_of(n, i + HEX_CORNER(1, c), j + HEX_CORNER(2, c), &
                                 k + HEX_CORNER(3, c))
          end do
        end do
      end do
    end do
  end subroutine cube_hexes

  !> Six Kuhn tetrahedra per hexahedron (conforming: every cube face split along the same
  !> diagonal), ordered for a positive volume.
  subroutine cube_tets(n, x, conn)
    integer, intent(in) :: n                      !< cells per edge
    real(wp), intent(in) :: x(:,:)                !< nodes
    integer, allocatable, intent(out) :: conn(:,:)   !< (4, 6 n^3)
    integer :: i, j, k, t, e, corner(3, 4), v, p(4)
    allocate(conn(4, 6*n**3))
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
              p(v) = node_of(n, i + corner(1, v), j + corner(2, v), k + corner(3, v))
            end do
            if (tet_volume(x(:, p)) < 0.0_wp) p(2:3) = p(3:2:-1)
            e = e + 1
            conn(:, e) = p
          end do
        end do
      end do
    end do
  end subroutine cube_tets

  !> Signed volume of a tetrahedron.
  pure real(wp) function tet_volume(xt)
    real(wp), intent(in) :: xt(3, 4)   !< corners
    tet_volume = dot_product(cross3(xt(:, 2) - xt(:, 1), xt(:, 3) - xt(:, 1)), &
                             xt(:, 4) - xt(:, 1))/6.0_wp
  end function tet_volume

  !> Cross product.
  pure function cross3(a, b) result(c)
    real(wp), intent(in) :: a(3), b(3)   !< vectors
    real(wp) :: c(3)
    c = [a(2)*b(3) - a(3)*b(2), a(3)*b(1) - a(1)*b(3), a(1)*b(2) - a(2)*b(1)]
  end function cross3

  ! ------------------------------------------------------------------ surface checks

  !> Checks shared by closed surfaces of a convex body: total area, zero sum of area vectors,
  !> every normal pointing away from the centre at the distance of its face (the face planes
  !> of a box: (c_f - centre).n = half the box size along the face normal), local numbering.
  subroutine check_closed_box(model, surface, centre, half, want_area, want_facets, name)
    type(model_t), intent(in) :: model                !< the model
    type(contact_surface_t), intent(in) :: surface    !< the surface
    real(wp), intent(in) :: centre(3), half(3)        !< box centre and half sizes
    real(wp), intent(in) :: want_area                 !< closed-form area
    integer, intent(in) :: want_facets                !< expected facet count
    character(len=*), intent(in) :: name              !< check prefix
    real(wp) :: a(3), total, sum_a(3), cf(3), worst, dist
    integer :: f, i, d
    logical :: ok_local, ok_element
    call check_equal(surface%nfacet, want_facets, name//': facet count')
    total = 0.0_wp
    sum_a = 0.0_wp
    worst = 0.0_wp
    ok_local = .true.
    ok_element = .true.
    do f = 1, surface%nfacet
      a = contact_facet_area_vector(surface, f, model%nodes%x)
      total = total + norm2(a)
      sum_a = sum_a + a
      cf = sum(model%nodes%x(:, surface%facets(1:surface%nvertex(f), f)), dim=2)/ &
           surface%nvertex(f)
      ! the unit normal is an axis direction d; the face lies at centre +- half(d)
      d = maxloc(abs(a), dim=1)
      dist = dot_product(cf - centre, a/norm2(a))
      worst = max(worst, abs(dist - half(d)), norm2(a/norm2(a)) - abs(a(d))/norm2(a))
      do i = 1, surface%nvertex(f)
        if (surface%nodes(surface%local(i, f)) /= surface%facets(i, f)) ok_local = .false.
        if (.not. any(model%elements%conn(:, surface%element(f)) == surface%facets(i, f))) &
          ok_element = .false.
      end do
    end do
    call check_close(total, want_area, TIGHT, name//': total area')
    call check_close(norm2(sum_a), 0.0_wp, 0.0_wp, name//': sum of area vectors = 0', &
                     atol=TIGHT)
    ! measured worst 2.2e-16
    call check(worst <= TIGHT, name//': every normal an outward axis at the face plane', &
               'worst deviation '//rtoa_local(worst))
    call check(all(surface%outward(1:surface%nfacet)), name//': all flagged outward')
    call check(ok_local, name//': nodes(local) = facets')
    call check(ok_element, name//': facet nodes belong to the owning element')
    call check(all(surface%nodes(2:) > surface%nodes(:surface%nnode-1)), &
               name//': surface nodes ascending and distinct')
  end subroutine check_closed_box

  !> Real to text for details.
  function rtoa_local(v) result(s)
    real(wp), intent(in) :: v   !< value
    character(len=24) :: s
    write(s, '(es24.16)') v
  end function rtoa_local

  ! ------------------------------------------------------------------ surface tests

  !> Exterior faces of a cube of 6 x 27 tetrahedra with moved interior nodes: 2 triangles
  !> per cube-face cell, area 6, outward; boundary nodes (n+1)^3 - (n-1)^3.
  subroutine test_cube_of_tets()
    integer, parameter :: N = 3
    type(model_t) :: model
    type(contact_surface_t) :: surface
    type(status_t) :: status
    real(wp), allocatable :: x(:,:)
    integer, allocatable :: conn(:,:)
    call cube_nodes(N, 0.2_wp/N, x)
    call cube_tets(N, x, conn)
    call make_model(model, 3, x, conn, spread(TOPO_TET4, 1, size(conn, 2)), &
                    spread(ELEM_SOLID, 1, size(conn, 2)), &
                    spread(1, 1, size(conn, 2)), 1)
    call contact_surface_build(model, SURFACE_PART, 1, surface, status)
    call check(status%ok, 'tet cube: built')
    if (.not. status%ok) return
    call check_equal(surface%dim, 3, 'tet cube: dimension')
    call check(all(surface%nvertex == 3) .and. all(surface%facets(4, :) == 0), &
               'tet cube: triangles, 4th node 0')
    call check_closed_box(model, surface, [0.5_wp, 0.5_wp, 0.5_wp], [0.5_wp, 0.5_wp, 0.5_wp], &
                          6.0_wp, 6*N*N*2, 'tet cube')
    call check_equal(surface%nnode, (N + 1)**3 - (N - 1)**3, 'tet cube: boundary nodes')
  end subroutine test_cube_of_tets

  !> A cube of tetrahedra in two parts (x < 1/2, x > 1/2): the part set of both gives the
  !> cube's surface; one part gives its own box, the shared plane included.
  subroutine test_two_parts()
    integer, parameter :: N = 4
    type(model_t) :: model
    type(contact_surface_t) :: surface
    type(status_t) :: status
    real(wp), allocatable :: x(:,:)
    integer, allocatable :: conn(:,:), part(:)
    integer :: e, s
    call cube_nodes(N, 0.0_wp, x)
    call cube_tets(N, x, conn)
    allocate(part(size(conn, 2)))
    do e = 1, size(conn, 2)
      part(e) = merge(1, 2, sum(x(1, conn(:, e)))/4 < 0.5_wp)
    end do
    call make_model(model, 3, x, conn, spread(TOPO_TET4, 1, size(conn, 2)), &
                    spread(ELEM_SOLID, 1, size(conn, 2)), part, 2)
    s = add_set(model, SET_PART, 5, [1, 2], 2)
    call contact_surface_build(model, SURFACE_PART_SET, s, surface, status)
    call check(status%ok, 'two parts: built')
    if (.not. status%ok) return
    call check_closed_box(model, surface, [0.5_wp, 0.5_wp, 0.5_wp], [0.5_wp, 0.5_wp, 0.5_wp], &
                          6.0_wp, 6*N*N*2, 'two parts, part set')
    call contact_surface_build(model, SURFACE_PART, 1, surface, status)
    ! box 0.5 x 1 x 1: area 2 (x faces) + 4 x 0.5; 2 x 16 x 2 + 4 x 8 x 2 triangles
    call check_closed_box(model, surface, [0.25_wp, 0.5_wp, 0.5_wp], &
                          [0.25_wp, 0.5_wp, 0.5_wp], 4.0_wp, 128, 'two parts, part 1')
  end subroutine test_two_parts

  !> Rigid tool solids: a box of 2^3 hexahedra (24 quads) and of 16 wedges (16 triangles on
  !> the z faces, 16 quads on the sides), area 6, outward.
  subroutine test_hex_and_wedge_boxes()
    integer, parameter :: N = 2
    type(model_t) :: model
    type(contact_surface_t) :: surface
    type(status_t) :: status
    real(wp), allocatable :: x(:,:)
    integer, allocatable :: hexes(:,:), wedges(:,:)
    integer :: e
    call cube_nodes(N, 0.0_wp, x)
    call cube_hexes(N, hexes)
    call make_model(model, 3, x, hexes, spread(TOPO_HEX8, 1, N**3), &
                    spread(ELEM_SOLID, 1, N**3), spread(1, 1, N**3), 1)
    call contact_surface_build(model, SURFACE_PART, 1, surface, status)
    call check(status%ok .and. all(surface%nvertex == 4), 'hex box: built, quadrilaterals')
    call check_closed_box(model, surface, [0.5_wp, 0.5_wp, 0.5_wp], [0.5_wp, 0.5_wp, 0.5_wp], &
                          6.0_wp, 6*N*N, 'hex box')
    call check_triangulated_hex_box(model, surface, N)
    allocate(wedges(6, 2*N**3))
    do e = 1, N**3
      wedges(:, 2*e-1) = hexes(HEX_WEDGES(:, 1), e)
      wedges(:, 2*e) = hexes(HEX_WEDGES(:, 2), e)
    end do
    call make_model(model, 3, x, wedges, spread(TOPO_PENTA6, 1, 2*N**3), &
                    spread(ELEM_SOLID, 1, 2*N**3), spread(1, 1, 2*N**3), 1)
    call contact_surface_build(model, SURFACE_PART, 1, surface, status)
    call check(status%ok, 'wedge box: built')
    call check_equal(count(surface%nvertex == 3), 2*N*N*2, 'wedge box: triangles on z faces')
    call check_closed_box(model, surface, [0.5_wp, 0.5_wp, 0.5_wp], [0.5_wp, 0.5_wp, 0.5_wp], &
                          6.0_wp, 2*N*N*2 + 4*N*N, 'wedge box')
  end subroutine test_hex_and_wedge_boxes

  !> The quadrilaterals of the hex box as the triangles of their two triangulations: 4 per
  !> quadrilateral, weight 1/2, half the face each (pieces 2), outward, the weighted area the
  !> box's, and every corner of a face a quarter of its area (a uniform nodal share).
  subroutine check_triangulated_hex_box(model, surface, n)
    type(model_t), intent(in) :: model               !< the hex box's model
    type(contact_surface_t), intent(inout) :: surface !< its surface (quadrilaterals)
    integer, intent(in) :: n                         !< elements per edge
    real(wp) :: a(3), area, centre(3), share(surface%nnode), face
    integer :: f, i
    call contact_surface_triangulate(surface)
    call check_equal(surface%nfacet, 4*6*n*n, 'triangulated hex box: 4 triangles per face')
    call check(all(surface%nvertex == 3) .and. all(surface%pieces == 2) .and. &
               all(surface%weight == 0.5_wp), 'triangulated hex box: weights 1/2, half faces')
    area = 0.0_wp
    share = 0.0_wp
    do f = 1, surface%nfacet
      a = contact_facet_area_vector(surface, f, model%nodes%x)
      centre = sum(model%nodes%x(:, surface%facets(1:3, f)), dim=2)/3.0_wp
      if (dot_product(a, centre - 0.5_wp) <= 0.0_wp) area = -huge(1.0_wp)   ! inward: fail
      area = area + surface%weight(f)*norm2(a)
      do i = 1, 3
        share(surface%local(i, f)) = share(surface%local(i, f)) + &
                                     surface%weight(f)*norm2(a)/3.0_wp
      end do
    end do
    call check_close(area, 6.0_wp, TIGHT, 'triangulated hex box: weighted area, outward')
    face = 1.0_wp/real(n*n, wp)
    ! a corner of the box is on 3 faces, an edge node on 2 x 2, a face node on 4
    call check(all(abs(share/(0.25_wp*face) - nint(share/(0.25_wp*face))) < 1e-12_wp), &
               'triangulated hex box: every corner of a face a quarter of its area')
  end subroutine check_triangulated_hex_box

  !> Segment sets listing the exterior of the tet cube and of the hex box with every other
  !> segment reversed (triangles stored N4 = N3, some with N4 = 0): the built facets equal
  !> the outward exterior faces; a segment on no element is kept as given, flagged.
  subroutine test_flipped_segments_3d()
    integer, parameter :: N = 2
    type(model_t) :: model
    type(contact_surface_t) :: exterior, surface
    type(status_t) :: status
    real(wp), allocatable :: x(:,:)
    integer, allocatable :: conn(:,:), members(:)
    integer :: f, s, nf, nv, nflipped
    ! tetrahedra
    call cube_nodes(N, 0.1_wp, x)
    call cube_tets(N, x, conn)
    call make_model(model, 3, x, conn, spread(TOPO_TET4, 1, size(conn, 2)), &
                    spread(ELEM_SOLID, 1, size(conn, 2)), &
                    spread(1, 1, size(conn, 2)), 1)
    call contact_surface_build(model, SURFACE_PART, 1, exterior, status)
    nf = exterior%nfacet
    allocate(members(4*nf))
    nflipped = 0
    do f = 1, nf
      members(4*f-3:4*f) = exterior%facets(:, f)
      members(4*f) = merge(0, members(4*f-1), mod(f, 3) == 0)   ! N4 = 0 or N4 = N3
      if (mod(f, 2) == 0) then
        members(4*f-2:4*f-1) = exterior%facets([3, 2], f)
        if (mod(f, 3) /= 0) members(4*f) = members(4*f-1)
        nflipped = nflipped + 1
      end if
    end do
    s = add_set(model, SET_SEGMENT, 3, members, nf)
    call contact_surface_build(model, SURFACE_SEGMENT_SET, s, surface, status)
    call check(status%ok, 'flipped triangles: built')
    if (.not. status%ok) return
    call check(nflipped > 0 .and. all(surface%facets == exterior%facets), &
               'flipped triangles: all re-oriented outward (equal the exterior faces)')
    call check(all(surface%element == exterior%element) .and. all(surface%outward), &
               'flipped triangles: adjacent tetrahedra found, flagged outward')
    ! hexahedra, quads reversed
    deallocate(members)
    call cube_nodes(N, 0.0_wp, x)
    call cube_hexes(N, conn)
    call make_model(model, 3, x, conn, spread(TOPO_HEX8, 1, N**3), &
                    spread(ELEM_SOLID, 1, N**3), spread(1, 1, N**3), 1)
    call contact_surface_build(model, SURFACE_PART, 1, exterior, status)
    nf = exterior%nfacet
    allocate(members(4*nf + 4))
    do f = 1, nf
      members(4*f-3:4*f) = exterior%facets(:, f)
      if (mod(f, 2) == 1) members(4*f-2:4*f) = exterior%facets([4, 3, 2], f)
    end do
    ! a segment on no element face (a diagonal plane of the first hexahedron, whose nodes it
    ! has): kept as given
    members(4*nf+1:4*nf+4) = [node_of(N, 0, 0, 0), node_of(N, 1, 0, 0), node_of(N, 1, 1, 1), &
                              node_of(N, 0, 1, 1)]
    s = add_set(model, SET_SEGMENT, 4, members, nf + 1)
    call contact_surface_build(model, SURFACE_SEGMENT_SET, s, surface, status)
    call check(status%ok, 'flipped quads: built')
    if (.not. status%ok) return
    call check(all(surface%facets(:, 1:nf) == exterior%facets) .and. &
               all(surface%outward(1:nf)), 'flipped quads: all re-oriented outward')
    nv = surface%nfacet
    call check(nv == nf + 1 .and. all(surface%facets(:, nv) == members(4*nf+1:4*nf+4)) .and. &
               surface%element(nv) == 0 .and. .not. surface%outward(nv), &
               'segment on no solid face: kept as given, element 0, not outward')
  end subroutine test_flipped_segments_3d

  !> 2D: a rectangle [0, 2] x [0, 1] of 4 x 3 x 2 counter-clockwise plane-strain triangles
  !> (shells) gives 14 boundary edges, perimeter 6, outward normals (t_y, -t_x); a rigid part
  !> of quadrilaterals numbered clockwise too; a segment set of reversed edges is re-oriented.
  subroutine test_2d_boundary_edges()
    integer, parameter :: NX = 4, NY = 3
    type(model_t) :: model
    type(contact_surface_t) :: surface, reference
    type(status_t) :: status
    real(wp), allocatable :: x(:,:)
    integer, allocatable :: tris(:,:), quads(:,:), members(:)
    integer :: i, j, e, f, s, p(4)
    allocate(x(3, (NX + 1)*(NY + 1)), tris(3, 2*NX*NY), quads(4, NX*NY))
    do j = 0, NY
      do i = 0, NX
        x(:, 1 + i + (NX + 1)*j) = [2.0_wp*i/NX, real(j, wp)/NY, 0.0_wp]
        ! move interior nodes: boundary edges unchanged
        if (i > 0 .and. i < NX .and. j > 0 .and. j < NY) x(1:2, 1 + i + (NX + 1)*j) = &
            x(1:2, 1 + i + (NX + 1)*j) + 0.1_wp*([noise(7*i + j), noise(5*j + i)] - 0.5_wp)
      end do
    end do
    e = 0
    do j = 0, NY - 1
      do i = 0, NX - 1
        p = [1 + i + (NX + 1)*j, 2 + i + (NX + 1)*j, 2 + i + (NX + 1)*(j + 1), &
             1 + i + (NX + 1)*(j + 1)]
        tris(:, 2*e+1) = p([1, 2, 3])
        tris(:, 2*e+2) = p([1, 3, 4])
        e = e + 1
        quads(:, e) = p([1, 4, 3, 2])            ! clockwise about +z
      end do
    end do
    call make_model(model, 2, x, tris, spread(TOPO_TRI3, 1, 2*NX*NY), &
                    spread(ELEM_SHELL, 1, 2*NX*NY), spread(1, 1, 2*NX*NY), 1)
    call contact_surface_build(model, SURFACE_PART, 1, surface, status)
    call check(status%ok .and. surface%dim == 2 .and. all(surface%nvertex == 2), &
               '2D triangles: built, edges')
    if (.not. status%ok) return
    call check_closed_box(model, surface, [1.0_wp, 0.5_wp, 0.0_wp], [1.0_wp, 0.5_wp, 0.0_wp], &
                          6.0_wp, 2*(NX + NY), '2D triangles')
    call check_equal(surface%nnode, 2*(NX + NY), '2D triangles: boundary nodes')
    reference = surface
    ! a segment set of the boundary edges, every other one reversed (stored N1 N2 N2 N2, or
    ! N1 N2 0 0)
    allocate(members(4*reference%nfacet))
    do f = 1, reference%nfacet
      if (mod(f, 2) == 0) then
        members(4*f-3:4*f) = [reference%facets(2, f), reference%facets(1, f), &
                              reference%facets(1, f), reference%facets(1, f)]
      else
        members(4*f-3:4*f) = [reference%facets(1:2, f), 0, 0]
      end if
    end do
    s = add_set(model, SET_SEGMENT, 8, members, reference%nfacet)
    call contact_surface_build(model, SURFACE_SEGMENT_SET, s, surface, status)
    call check(status%ok, '2D segments: built')
    if (.not. status%ok) return
    call check(all(surface%facets == reference%facets) .and. all(surface%outward) .and. &
               all(surface%element == reference%element), &
               '2D segments: reversed edges re-oriented (body on the left)')
    ! rigid tool quadrilaterals numbered clockwise
    call make_model(model, 2, x, quads, spread(TOPO_QUAD4, 1, NX*NY), &
                    spread(ELEM_SHELL, 1, NX*NY), spread(1, 1, NX*NY), 1)
    call contact_surface_build(model, SURFACE_PART, 1, surface, status)
    call check(status%ok, '2D clockwise quads: built')
    if (.not. status%ok) return
    call check_closed_box(model, surface, [1.0_wp, 0.5_wp, 0.0_wp], [1.0_wp, 0.5_wp, 0.0_wp], &
                          6.0_wp, 2*(NX + NY), '2D clockwise quads')
  end subroutine test_2d_boundary_edges

  !> 3D shells (a tool of 2 quadrilaterals and 2 triangles) become facets as numbered,
  !> flagged not outward.
  subroutine test_shells_as_facets()
    type(model_t) :: model
    type(contact_surface_t) :: surface
    type(status_t) :: status
    real(wp) :: x(3, 8)
    integer :: conn(4, 4), s
    x = reshape([0, 0, 0,  1, 0, 0,  2, 0, 0,  0, 1, 0,  1, 1, 0,  2, 1, 0,  0, 2, 0,  1, 2, 0], &
                [3, 8])*1.0_wp
    conn(:, 1) = [1, 2, 5, 4]
    conn(:, 2) = [2, 3, 6, 5]
    conn(:, 3) = [4, 5, 8, 0]
    conn(:, 4) = [4, 8, 7, 0]
    call make_model(model, 3, x, conn, [TOPO_QUAD4, TOPO_QUAD4, TOPO_TRI3, TOPO_TRI3], &
                    spread(ELEM_SHELL, 1, 4), [1, 1, 2, 2], 2)
    s = add_set(model, SET_PART, 2, [1, 2], 2)
    call contact_surface_build(model, SURFACE_PART_SET, s, surface, status)
    call check(status%ok, 'shells: built')
    if (.not. status%ok) return
    call check(surface%nfacet == 4 .and. all(surface%facets == conn) .and. &
               all(surface%nvertex == [4, 4, 3, 3]) .and. all(surface%element == [1, 2, 3, 4]), &
               'shells: facets = elements as numbered')
    call check(.not. any(surface%outward), 'shells: flagged not outward (side unknown)')
    call check(surface%nnode == 8 .and. all(surface%nodes == [1, 2, 3, 4, 5, 6, 7, 8]), &
               'shells: nodes')
    call check_close(norm2(contact_facet_area_vector(surface, 1, model%nodes%x) - &
                           [0.0_wp, 0.0_wp, 1.0_wp]), 0.0_wp, 0.0_wp, &
                     'shells: quad area vector (0, 0, 1)', atol=TIGHT)
  end subroutine test_shells_as_facets

  !> Failures: an empty SURFB names the contact id and SURFB; a contact without id; a
  !> triangle segment in a 2D model; a part set index given as a segment set; a solid in a
  !> 2D model; an unknown surface type.
  subroutine test_failures()
    type(model_t) :: model
    type(contact_surface_t) :: slave, master
    type(status_t) :: status
    real(wp) :: x(3, 4)
    integer :: conn(4, 1), s
    x = reshape([0, 0, 0,  1, 0, 0,  0, 1, 0,  0, 0, 1], [3, 4])*1.0_wp
    conn(:, 1) = [1, 2, 3, 4]
    call make_model(model, 3, x, conn, [TOPO_TET4], [ELEM_SOLID], [1], 2)
    allocate(model%contacts(1))
    model%n_contacts = 1
    model%contacts(1) = contact_t(id=7, surf_a_type=SURFACE_PART, surf_b_type=SURFACE_PART, &
                                  surf_a=1, surf_b=2)
    call contact_surface_pair_build(model, 1, slave, master, status)
    call check(.not. status%ok, 'empty SURFB: fails')
    if (.not. status%ok) call check(index(status%message, 'contact 7 SURFB') > 0 .and. &
        index(status%message, 'part 20') > 0, 'empty SURFB: message names contact 7, '// &
        'SURFB, part 20', status%message)
    if (.not. status%ok) write(*, '(a)') '  message: '//status%message
    call check(slave%nfacet == 4, 'empty SURFB: SURFA (one tetrahedron) has 4 facets')
    model%contacts(1)%id = 0
    model%contacts(1)%surf_b = 1
    model%contacts(1)%surf_a = 2
    call contact_surface_pair_build(model, 1, slave, master, status)
    call check(.not. status%ok, 'empty SURFA: fails')
    if (.not. status%ok) call check(index(status%message, 'contact number 1 (no id) SURFA') &
        > 0, 'empty SURFA without id: message', status%message)
    s = add_set(model, SET_PART, 3, [1], 1)
    call contact_surface_build(model, SURFACE_SEGMENT_SET, s, slave, status, 'contact 2 SURFA')
    call check(.not. status%ok .and. index(status%message, 'not a segment set') > 0, &
               'part set given as a segment set: fails')
    call contact_surface_build(model, 1, s, slave, status)
    call check(.not. status%ok .and. index(status%message, 'surface type 1') > 0, &
               'surface type 1 (shell set): fails')
    model%dimension = 2
    call contact_surface_build(model, SURFACE_PART, 1, slave, status)
    call check(.not. status%ok .and. index(status%message, 'solid in a 2D model') > 0, &
               'solid in a 2D model: fails')
    s = add_set(model, SET_SEGMENT, 4, [1, 2, 3, 3], 1)
    call contact_surface_build(model, SURFACE_SEGMENT_SET, s, slave, status)
    call check(.not. status%ok .and. index(status%message, 'is not a line') > 0, &
               'triangle segment in a 2D model: fails', status%message)
  end subroutine test_failures

  ! ------------------------------------------------------------------ search

  !> A grid surface of nx x ny cells over [x0, x0 + lx] x [y0, y0 + ly] (triangles or
  !> quadrilaterals), heights z0 + amp sin, interior nodes moved in x, y; appended to x.
  subroutine grid_surface(nx, ny, x0, y0, lx, ly, z0, amp, triangles, seed, x, nnode, surface)
    integer, intent(in) :: nx, ny                     !< cells
    real(wp), intent(in) :: x0, y0, lx, ly, z0, amp   !< placement and waviness
    logical, intent(in) :: triangles                  !< two triangles per cell
    integer, intent(in) :: seed                       !< noise seed
    real(wp), intent(inout) :: x(:,:)                 !< coordinates (room enough)
    integer, intent(inout) :: nnode                   !< nodes used in x
    type(contact_surface_t), intent(out) :: surface   !< the surface
    integer :: i, j, base, f, p(4)
    real(wp) :: hx, hy
    base = nnode
    hx = lx/nx
    hy = ly/ny
    do j = 0, ny
      do i = 0, nx
        nnode = nnode + 1
        x(:, nnode) = [x0 + i*hx, y0 + j*hy, z0]
        if (i > 0 .and. i < nx .and. j > 0 .and. j < ny) x(1:2, nnode) = x(1:2, nnode) + &
            0.3_wp*[hx, hy]*([noise(seed + 2*nnode), noise(seed + 2*nnode + 1)] - 0.5_wp)
        x(3, nnode) = z0 + amp*sin(3.0_wp*x(1, nnode) + 2.0_wp*x(2, nnode))
      end do
    end do
    surface%dim = 3
    surface%nfacet = merge(2, 1, triangles)*nx*ny
    allocate(surface%facets(4, surface%nfacet), surface%nvertex(surface%nfacet))
    surface%facets = 0
    f = 0
    do j = 0, ny - 1
      do i = 0, nx - 1
        p = base + [1 + i + (nx + 1)*j, 2 + i + (nx + 1)*j, 2 + i + (nx + 1)*(j + 1), &
                    1 + i + (nx + 1)*(j + 1)]
        if (triangles) then
          surface%facets(1:3, f + 1) = p([1, 2, 3])
          surface%facets(1:3, f + 2) = p([1, 3, 4])
          surface%nvertex(f + 1:f + 2) = 3
          f = f + 2
        else
          f = f + 1
          surface%facets(:, f) = p
          surface%nvertex(f) = 4
        end if
      end do
    end do
  end subroutine grid_surface

  !> Brute-force reference: every (slave, master) pair with overlapping boxes, the master box
  !> enlarged by margin (same arithmetic as the search), in slave-then-master order.
  subroutine brute_force_pairs(slave, master, x, margin, pairs, npairs)
    type(contact_surface_t), intent(in) :: slave, master   !< surfaces
    real(wp), intent(in) :: x(:,:)                         !< coordinates
    real(wp), intent(in) :: margin                         !< enlargement
    integer, allocatable, intent(out) :: pairs(:,:)        !< pairs
    integer, intent(out) :: npairs                         !< count
    real(wp) :: slo(3, slave%nfacet), shi(3, slave%nfacet)
    real(wp) :: mlo(3, master%nfacet), mhi(3, master%nfacet)
    integer :: s, m, d
    d = slave%dim
    do s = 1, slave%nfacet
      call facet_box(slave, s, x, d, slo(:, s), shi(:, s))
    end do
    do m = 1, master%nfacet
      call facet_box(master, m, x, d, mlo(:, m), mhi(:, m))
      mlo(1:d, m) = mlo(1:d, m) - margin
      mhi(1:d, m) = mhi(1:d, m) + margin
    end do
    allocate(pairs(2, 1024))
    npairs = 0
    do s = 1, slave%nfacet
      do m = 1, master%nfacet
        if (any(slo(1:d, s) > mhi(1:d, m)) .or. any(shi(1:d, s) < mlo(1:d, m))) cycle
        if (npairs == size(pairs, 2)) pairs = reshape(pairs, [2, 2*npairs], pad=[0])
        npairs = npairs + 1
        pairs(:, npairs) = [s, m]
      end do
    end do
  end subroutine brute_force_pairs

  !> Box of a facet over the first d coordinates (reference implementation).
  subroutine facet_box(surface, f, x, d, lo, hi)
    type(contact_surface_t), intent(in) :: surface   !< surface
    integer, intent(in) :: f, d                      !< facet, dimensions
    real(wp), intent(in) :: x(:,:)                   !< coordinates
    real(wp), intent(out) :: lo(3), hi(3)            !< box
    integer :: i
    lo = 0.0_wp
    hi = 0.0_wp
    lo(1:d) = huge(1.0_wp)
    hi(1:d) = -huge(1.0_wp)
    do i = 1, surface%nvertex(f)
      lo(1:d) = min(lo(1:d), x(1:d, surface%facets(i, f)))
      hi(1:d) = max(hi(1:d), x(1:d, surface%facets(i, f)))
    end do
  end subroutine facet_box

  !> Search and brute force agree pair by pair (same order); for each margin.
  subroutine compare_with_brute_force(slave, master, x, margins, name)
    type(contact_surface_t), intent(in) :: slave, master   !< surfaces
    real(wp), intent(in) :: x(:,:)                         !< coordinates
    real(wp), intent(in) :: margins(:)                     !< margins tried
    character(len=*), intent(in) :: name                   !< check prefix
    type(contact_search_t) :: search
    integer, allocatable :: pairs(:,:), reference(:,:)
    integer :: npairs, nref, k
    character(len=16) :: tag
    do k = 1, size(margins)
      write(tag, '(a,es9.2)') ' margin', margins(k)
      call contact_search_build(search, slave, master, x, margins(k), pairs, npairs)
      call brute_force_pairs(slave, master, x, margins(k), reference, nref)
      call check(npairs == nref .and. npairs > 0, name//trim(tag)//': pair count = brute '// &
                 'force', 'search '//itoa_local(npairs)//' brute force '//itoa_local(nref))
      if (npairs /= nref) cycle
      call check(all(pairs(:, 1:npairs) == reference(:, 1:nref)), name//trim(tag)// &
                 ': same pairs in the same order (slave, then master)')
      write(*, '(a,a,a,a,i0,a,i0,a,i0,a,i0,a,i0,a)') '  ', name, trim(tag), ': ', slave%nfacet, &
          ' slave x ', master%nfacet, ' master facets: ', npairs, ' pairs, ', &
          search%n_box_tests, ' box tests (brute force ', &
          int(slave%nfacet, i8)*master%nfacet, ')'
    end do
  end subroutine compare_with_brute_force

  !> Integer to text.
  function itoa_local(i) result(s)
    integer, intent(in) :: i   !< value
    character(len=12) :: s
    write(s, '(i0)') i
  end function itoa_local

  !> 3D: a wavy triangulated slave (1500 facets) under a wavy, shifted master of quads
  !> (over a larger area, coarser): the search equals brute force for three margins, and every
  !> facet pair with a slave and a master vertex closer than the margin is a candidate.
  subroutine test_search_3d()
    type(contact_surface_t) :: slave, master
    type(contact_search_t) :: search
    real(wp), allocatable :: x(:,:)
    real(wp), parameter :: MARGIN = 0.03_wp
    integer, allocatable :: pairs(:,:)
    integer :: nnode, npairs, s, m, i, j, missing, close_pairs
    allocate(x(3, 2000))
    nnode = 0
    call grid_surface(30, 25, 0.0_wp, 0.0_wp, 1.0_wp, 1.0_wp, 0.0_wp, 0.03_wp, .true., 11, x, &
                      nnode, slave)
    call grid_surface(17, 21, -0.1_wp, -0.05_wp, 1.3_wp, 1.1_wp, 0.02_wp, -0.04_wp, .false., &
                      29, x, nnode, master)
    call compare_with_brute_force(slave, master, x(:, 1:nnode), [0.0_wp, MARGIN, 0.3_wp], &
                                  'search 3D')
    call contact_search_build(search, slave, master, x(:, 1:nnode), MARGIN, pairs, npairs)
    missing = 0
    close_pairs = 0
    do s = 1, slave%nfacet
      do m = 1, master%nfacet
        if (.not. any([((norm2(x(:, slave%facets(i, s)) - x(:, master%facets(j, m))) < &
                         MARGIN, i = 1, 3), j = 1, 4)])) cycle
        close_pairs = close_pairs + 1
        if (.not. has_pair(pairs, npairs, s, m)) missing = missing + 1
      end do
    end do
    call check(close_pairs > 0 .and. missing == 0, 'search 3D: no pair missing with '// &
               'vertices within the margin', itoa_local(missing)//' of '//itoa_local(close_pairs))
  end subroutine test_search_3d

  !> True when (s, m) is among the sorted pairs (bisection).
  logical function has_pair(pairs, npairs, s, m)
    integer, intent(in) :: pairs(:,:), npairs, s, m   !< sorted pairs, the pair sought
    integer :: low, high, mid
    low = 1
    high = npairs
    has_pair = .false.
    do while (low <= high)
      mid = (low + high)/2
      if (pairs(1, mid) == s .and. pairs(2, mid) == m) then
        has_pair = .true.
        return
      end if
      if (pairs(1, mid) < s .or. (pairs(1, mid) == s .and. pairs(2, mid) < m)) then
        low = mid + 1
      else
        high = mid - 1
      end if
    end do
  end function has_pair

  !> 2D: a slave circle of 300 edges (radius 1) and a master wavy line of 120 edges crossing
  !> it; z differs per node and must be ignored.
  subroutine test_search_2d()
    integer, parameter :: NS = 300, NM = 120
    type(contact_surface_t) :: slave, master
    real(wp) :: x(3, NS + NM + 1), angle
    integer :: i
    do i = 1, NS
      angle = 2.0_wp*acos(-1.0_wp)*(i - 1 + 0.3_wp*noise(i))/NS
      x(:, i) = [cos(angle), sin(angle), 5.0_wp*noise(3*i)]
    end do
    do i = 0, NM
      x(:, NS + 1 + i) = [-1.5_wp + 3.0_wp*i/NM, 0.9_wp + 0.2_wp*sin(7.0_wp*i/NM), &
                          -5.0_wp*noise(5*i)]
    end do
    slave%dim = 2
    slave%nfacet = NS
    allocate(slave%facets(4, NS), slave%nvertex(NS))
    slave%facets = 0
    slave%nvertex = 2
    do i = 1, NS
      slave%facets(1:2, i) = [i, modulo(i, NS) + 1]
    end do
    master%dim = 2
    master%nfacet = NM
    allocate(master%facets(4, NM), master%nvertex(NM))
    master%facets = 0
    master%nvertex = 2
    do i = 1, NM
      master%facets(1:2, i) = [NS + i, NS + i + 1]
    end do
    call compare_with_brute_force(slave, master, x, [0.0_wp, 0.02_wp, 0.2_wp], 'search 2D')
  end subroutine test_search_2d

  !> A second call with the same sizes allocates nothing and gives the same pairs; so does a
  !> call on a smaller master; a larger one grows the arrays.
  subroutine test_search_reuse()
    type(contact_surface_t) :: slave, master, small, large
    type(contact_search_t) :: search
    real(wp), allocatable :: x(:,:)
    integer, allocatable :: pairs(:,:), first(:,:)
    integer :: nnode, npairs, nfirst, grows
    allocate(x(3, 4000))
    nnode = 0
    call grid_surface(20, 20, 0.0_wp, 0.0_wp, 1.0_wp, 1.0_wp, 0.0_wp, 0.02_wp, .true., 3, x, &
                      nnode, slave)
    call grid_surface(15, 15, 0.0_wp, 0.0_wp, 1.0_wp, 1.0_wp, 0.01_wp, 0.02_wp, .false., 5, x, &
                      nnode, master)
    call grid_surface(6, 6, 0.2_wp, 0.2_wp, 0.5_wp, 0.5_wp, 0.01_wp, 0.02_wp, .false., 7, x, &
                      nnode, small)
    call grid_surface(30, 30, 0.0_wp, 0.0_wp, 1.0_wp, 1.0_wp, 0.01_wp, 0.02_wp, .true., 9, x, &
                      nnode, large)
    call contact_search_build(search, slave, master, x(:, 1:nnode), 0.01_wp, pairs, npairs)
    first = pairs(:, 1:npairs)
    nfirst = npairs
    grows = search%n_grows
    call contact_search_build(search, slave, master, x(:, 1:nnode), 0.01_wp, pairs, npairs)
    call check(search%n_grows == grows, 'reuse: same sizes, no reallocation')
    call check(npairs == nfirst .and. all(pairs(:, 1:npairs) == first), &
               'reuse: deterministic (same pairs, same order)')
    call contact_search_build(search, slave, small, x(:, 1:nnode), 0.01_wp, pairs, npairs)
    call check(search%n_grows == grows .and. npairs > 0, 'reuse: smaller master, no '// &
               'reallocation')
    call contact_search_build(search, slave, large, x(:, 1:nnode), 0.01_wp, pairs, npairs)
    call check(search%n_grows > grows .and. npairs > 0, 'reuse: larger master, arrays grown')
  end subroutine test_search_reuse

  !> A master of two small patches 1000 patch sizes apart (a box mostly empty): the grid is
  !> capped at 32 cells per master facet and the pairs still equal brute force.
  subroutine test_search_sparse_master()
    type(contact_surface_t) :: slave, master, far
    type(contact_search_t) :: search
    real(wp), allocatable :: x(:,:)
    integer, allocatable :: pairs(:,:)
    integer :: nnode, npairs, nm
    allocate(x(3, 400))
    nnode = 0
    call grid_surface(8, 8, 0.0_wp, 0.0_wp, 1.0_wp, 1.0_wp, 0.0_wp, 0.05_wp, .true., 19, x, &
                      nnode, slave)
    call grid_surface(5, 5, 0.1_wp, 0.1_wp, 1.0_wp, 1.0_wp, 0.02_wp, 0.05_wp, .false., 23, x, &
                      nnode, master)
    call grid_surface(5, 5, 1000.0_wp, 1000.0_wp, 1.0_wp, 1.0_wp, 1000.0_wp, 0.05_wp, .false., &
                      31, x, nnode, far)
    ! one master surface of both patches
    nm = master%nfacet + far%nfacet
    master%facets = reshape([master%facets, far%facets], [4, nm])
    master%nvertex = [master%nvertex, far%nvertex]
    master%nfacet = nm
    call contact_search_build(search, slave, master, x(:, 1:nnode), 0.05_wp, pairs, npairs)
    call check(product(search%ncell) <= 32*nm, 'sparse master: at most 32 cells per '// &
               'master facet', 'cells '//itoa_local(product(search%ncell)))
    call compare_with_brute_force(slave, master, x(:, 1:nnode), [0.05_wp], 'sparse master')
  end subroutine test_search_sparse_master

  !> 50 000 slave triangles over 16 000 master quadrilaterals: time of the first call (arrays
  !> allocated) and of a repeated call; box tests per slave facet (O(n): bounded, against
  !> 16 000 per facet for brute force).
  subroutine test_search_timing()
    type(contact_surface_t) :: slave, master
    type(contact_search_t) :: search
    real(wp), allocatable :: x(:,:)
    integer, allocatable :: pairs(:,:)
    integer :: nnode, npairs, t0, t1, t2, rate
    real(wp) :: per_facet
    allocate(x(3, 126*201 + 101*161))
    nnode = 0
    call grid_surface(125, 200, 0.0_wp, 0.0_wp, 1.0_wp, 1.6_wp, 0.0_wp, 0.02_wp, .true., 13, &
                      x, nnode, slave)
    call grid_surface(100, 160, 0.0_wp, 0.0_wp, 1.0_wp, 1.6_wp, 0.005_wp, 0.02_wp, .false., &
                      17, x, nnode, master)
    call system_clock(t0, rate)
    call contact_search_build(search, slave, master, x, 0.005_wp, pairs, npairs)
    call system_clock(t1)
    call contact_search_build(search, slave, master, x, 0.005_wp, pairs, npairs)
    call system_clock(t2)
    per_facet = real(search%n_box_tests, wp)/slave%nfacet
    write(*, '(a,i0,a,i0,a,f8.4,a,f8.4,a,i0,a,f6.2,a,f7.3,a)') '  search timing: ', &
        slave%nfacet, ' slave x ', master%nfacet, ' master facets: first call ', &
        real(t1 - t0, wp)/rate, ' s, repeated call ', real(t2 - t1, wp)/rate, ' s; ', &
        npairs, ' pairs, ', per_facet, ' box tests per slave facet, cell size ', &
        search%cell_size
    call check_equal(slave%nfacet, 50000, 'timing: 50 000 slave facets')
    ! measured 16.4 box tests per slave facet (7.9 pairs per slave facet); 0.011-0.022 s per
    ! call in the release build, 0.05-0.07 s in the debug build (shared 2-core machine)
    call check(npairs > 0 .and. per_facet < 30.0_wp, 'timing: O(n) search, < 30 box tests '// &
               'per slave facet')
  end subroutine test_search_timing

  !> Time of the exterior-face extraction of a 20 x 20 x 20 cube of 48 000 tetrahedra.
  subroutine test_extraction_timing()
    integer, parameter :: N = 20
    type(model_t) :: model
    type(contact_surface_t) :: surface
    type(status_t) :: status
    real(wp), allocatable :: x(:,:)
    integer, allocatable :: conn(:,:)
    integer :: t0, t1, rate
    call cube_nodes(N, 0.0_wp, x)
    call cube_tets(N, x, conn)
    call make_model(model, 3, x, conn, spread(TOPO_TET4, 1, size(conn, 2)), &
                    spread(ELEM_SOLID, 1, size(conn, 2)), &
                    spread(1, 1, size(conn, 2)), 1)
    call system_clock(t0, rate)
    call contact_surface_build(model, SURFACE_PART, 1, surface, status)
    call system_clock(t1)
    write(*, '(a,i0,a,i0,a,f8.4,a)') '  extraction timing: ', size(conn, 2), ' tetrahedra -> ', &
        surface%nfacet, ' exterior facets in ', real(t1 - t0, wp)/rate, ' s'
    call check(status%ok .and. surface%nfacet == 6*N*N*2, 'extraction timing: facet count')
  end subroutine test_extraction_timing

end program test_contact_surfaces
