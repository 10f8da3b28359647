!> Smoothing domains of the meshfree-enriched FEM: one per edge (2D triangles) or face
!> (3D tetrahedra) of a simplex mesh (formulation.md sections 2.3 and 2.6).
!>
!> Each element is split into nvert sub-simplices (centroid + one side each); the smoothing
!> domain of a side is the union of the sub-simplices on it, one or two, with weight
!> A_m = sum over its elements of A_e/3 (2D) or V_e/4 (3D). The deformation gradient,
!> stress and history are stored per domain.
!>
!> Local numbering (also used by the element kernels):
!> - triangle (corners 1-2-3 counter-clockwise in the x-y plane): edge k is opposite corner k,
!>   TRIANGLE_EDGE_CORNERS(:,k) = (2,3), (3,1), (1,2), each in counter-clockwise order, so the
!>   body lies to the left of a -> b and the outward normal is t x e_z = (t_y, -t_x),
!>   t = x_b - x_a;
!> - tetrahedron (1-2-3 counter-clockwise seen from 4, i.e. positive volume): face k is
!>   opposite corner k, TETRAHEDRON_FACE_CORNERS(:,k) = (2,3,4), (1,4,3), (1,2,4), (1,3,2),
!>   each ordered so that the right-hand normal (x_b - x_a) x (x_c - x_a) points out of the
!>   element.
!> Domain numbering: by first appearance, scanning elements 1..nelem and their sides 1..nvert,
!> so domain_elem(1,m) < domain_elem(2,m) and the domains follow the element order.
!> domain_nodes(:,m) are the side's corners in the outward order of element domain_elem(1,m):
!> on the boundary the right-hand normal points out of the body (contact surfaces, pressure
!> loads); inside, it points from domain_elem(1,m) into domain_elem(2,m).
!>
!> Construction is linear in the mesh size: the sides are sorted by their sorted node tuples
!> with a stable least-significant-digit radix sort (one counting sort over node indices per
!> tuple entry), and equal tuples are adjacent. Pure data: no MPI.
module mefem_smoothing_domains
  use mefem_kinds, only: wp
  use mefem_vector_math, only: cross
  use mefem_errors, only: status_t
  use mefem_index_lists, only: sort_small
  implicit none
  private

  public :: smoothing_domains_build, smoothing_domains_geometry, smoothing_domains_count, &
            simplex_geometry

  !> Corners of triangle edge k (opposite corner k), counter-clockwise (outward to the right).
  integer, parameter, public :: TRIANGLE_EDGE_CORNERS(2, 3) = &
      reshape([2, 3,  3, 1,  1, 2], [2, 3])
  !> Corners of tetrahedron face k (opposite corner k), right-hand normal pointing out.
  integer, parameter, public :: TETRAHEDRON_FACE_CORNERS(3, 4) = &
      reshape([2, 3, 4,  1, 4, 3,  1, 2, 4,  1, 3, 2], [3, 4])

  !> Problems spelled out in status%message; further ones are only counted.
  integer, parameter :: MAX_REPORTED = 5

  !> Smoothing domains (edges or faces) of a simplex mesh, their adjacency and geometry.
  type, public :: smoothing_domains_t
    integer :: ndim = 0                       !< 2 (triangles) or 3 (tetrahedra)
    integer :: nvert = 0                      !< corners per element: 3 or 4
    integer :: nside_nodes = 0                !< corners per side: 2 or 3
    integer :: nelem = 0                      !< elements
    integer :: ndomain = 0                    !< edges (2D) or faces (3D) of the mesh
    integer :: nboundary = 0                  !< domains with one element
    integer, allocatable :: domain_elem(:,:)  !< (2, ndomain) adjacent elements, 0 = none
                                              !< (boundary: slot 2 is 0); slot 1 < slot 2
    integer, allocatable :: domain_local(:,:) !< (2, ndomain) local side number of the domain
                                              !< in each adjacent element (0 = none)
    integer, allocatable :: elem_domain(:,:)  !< (nvert, nelem) domain of local side k
    integer, allocatable :: domain_nodes(:,:) !< (nside_nodes, ndomain) corners, outward
                                              !< order of element domain_elem(1,m)
    logical, allocatable :: is_boundary(:)    !< (ndomain) one adjacent element only
    integer, allocatable :: boundary_list(:)  !< (nboundary) boundary domains, ascending
    real(wp), allocatable :: elem_measure(:)  !< (nelem) element area (2D) / volume (3D)
    real(wp), allocatable :: altitude(:,:)    !< (nvert, nelem) distance from corner k to the
                                              !< line/plane of side k
    real(wp), allocatable :: inward_normal(:,:,:) !< (3, nvert, nelem) unit normal of side k
                                              !< pointing into the element (z = 0 in 2D)
    real(wp), allocatable :: side_measure(:)  !< (ndomain) edge length (2D) / face area (3D)
    real(wp), allocatable :: domain_weight(:) !< (ndomain) A_m = sum A_e/3 (2D), V_e/4 (3D)
  end type smoothing_domains_t

contains

  !> Build the smoothing domains of a triangle or tetrahedron mesh and their reference
  !> geometry. Invalid meshes (node out of range, repeated corner, side shared by more than
  !> two elements or twice with the same orientation, non-positive area/volume) are reported
  !> through status naming the elements; domains is then not to be used. `lean` keeps only
  !> what the cells need (domain_elem, domain_local, elem_measure, domain_weight, nboundary):
  !> no per-side lists, altitudes, normals or side measures (simplex_geometry gives an
  !> element's on demand), 180 of 250 bytes per element less at the set-up's peak.
  subroutine smoothing_domains_build(conn, x, domains, status, element_ids, lean)
    integer, intent(in) :: conn(:,:)                 !< (nvert, nelem) corners, 1-based,
                                                     !< positively oriented; nvert = 3 or 4
    real(wp), intent(in) :: x(:,:)                   !< (3, nnode) reference coordinates
                                                     !< (2D uses x(1:2,:))
    type(smoothing_domains_t), intent(out) :: domains !< the result
    type(status_t), intent(out) :: status            !< failure and its reason
    integer, intent(in), optional :: element_ids(:)  !< (nelem) user ids used in messages
    logical, intent(in), optional :: lean            !< the cells' arrays only (above)
    integer, allocatable :: side_group(:)
    integer :: nvert, nelem, nside_nodes, ngroup, nproblem
    logical :: lean_build

    nvert = size(conn, 1)
    nelem = size(conn, 2)
    nproblem = 0
    if (nvert /= 3 .and. nvert /= 4) then
      call add_problem(status, nproblem, 'elements must have 3 or 4 '// &
          'corners (got '//int_text(nvert)//')')
    else if (size(x, 1) < nvert - 1) then
      call add_problem(status, nproblem, 'coordinates need '// &
          int_text(nvert - 1)//' components')
    else if (present(element_ids)) then
      if (size(element_ids) < nelem) call add_problem(status, nproblem, &
          'fewer element ids than elements')
    end if
    if (nproblem > 0) return
    nside_nodes = nvert - 1

    call check_corners(conn, size(x, 2), status, nproblem, element_ids)
    if (nproblem > 0) then
      call close_report(status, nproblem)
      return
    end if

    call group_sides(conn, side_group, ngroup, status, nproblem, element_ids)
    if (nproblem > 0) then
      call close_report(status, nproblem)
      return
    end if

    domains%ndim = nvert - 1
    domains%nvert = nvert
    domains%nside_nodes = nside_nodes
    domains%nelem = nelem
    lean_build = .false.
    if (present(lean)) lean_build = lean
    call number_domains(conn, side_group, ngroup, domains, lean_build)
    deallocate(side_group)

    call smoothing_domains_geometry(domains, conn, x, status, element_ids, lean_build)
  end subroutine smoothing_domains_build

  !> Compute element measures, altitudes, inward normals, side measures and domain weights
  !> for coordinates x (the reference configuration, or any other one for re-use); `lean`:
  !> the element measures and domain weights only.
  !> A non-positive area/volume is reported through status (all such elements counted).
  subroutine smoothing_domains_geometry(domains, conn, x, status, element_ids, lean)
    type(smoothing_domains_t), intent(inout) :: domains !< topology built; geometry filled
    integer, intent(in) :: conn(:,:)                 !< (nvert, nelem) corners
    real(wp), intent(in) :: x(:,:)                   !< (3, nnode) coordinates
    type(status_t), intent(out) :: status            !< failure and its reason
    integer, intent(in), optional :: element_ids(:)  !< (nelem) user ids used in messages
    logical, intent(in), optional :: lean            !< measures and weights only
    real(wp) :: altitude(4), normal(3, 4), side_size(4)
    integer :: e, j, m, nproblem
    logical :: keep

    nproblem = 0
    if (allocated(domains%elem_measure)) deallocate(domains%elem_measure)
    if (allocated(domains%altitude)) deallocate(domains%altitude)
    if (allocated(domains%inward_normal)) deallocate(domains%inward_normal)
    if (allocated(domains%side_measure)) deallocate(domains%side_measure)
    if (allocated(domains%domain_weight)) deallocate(domains%domain_weight)
    keep = .true.
    if (present(lean)) keep = .not. lean
    allocate(domains%elem_measure(domains%nelem))
    if (keep) then
      allocate(domains%altitude(domains%nvert, domains%nelem))
      allocate(domains%inward_normal(3, domains%nvert, domains%nelem))
      allocate(domains%side_measure(domains%ndomain))
    end if

    do e = 1, domains%nelem
      call simplex_geometry(x(:, conn(:, e)), domains%elem_measure(e), &
                            altitude(1:domains%nvert), normal(:, 1:domains%nvert), &
                            side_size(1:domains%nvert))
      if (.not. (domains%elem_measure(e) > 0.0_wp .and. &
                 minval(side_size(1:domains%nvert)) > 0.0_wp)) &
        call add_problem(status, nproblem,  &
          element_name(e, element_ids)//' has a non-positive '// &
          trim(merge('area  ', 'volume', domains%nvert == 3))//' ('// &
          real_text(domains%elem_measure(e))//'; inverted or degenerate)')
      if (.not. keep) cycle
      domains%altitude(:, e) = altitude(1:domains%nvert)
      domains%inward_normal(:, :, e) = normal(:, 1:domains%nvert)
      do j = 1, domains%nvert                 ! the side measure, from its first element
        m = domains%elem_domain(j, e)
        if (domains%domain_elem(1, m) == e) domains%side_measure(m) = side_size(j)
      end do
    end do
    if (nproblem > 0) call close_report(status, nproblem)

    allocate(domains%domain_weight(domains%ndomain))
    do m = 1, domains%ndomain
      domains%domain_weight(m) = 0.0_wp
      do j = 1, 2
        e = domains%domain_elem(j, m)
        if (e > 0) domains%domain_weight(m) = domains%domain_weight(m) + &
            domains%elem_measure(e)/real(domains%nvert, wp)
      end do
    end do
  end subroutine smoothing_domains_geometry

  !> Every corner must be a node index in 1..nnode and the corners of an element distinct.
  subroutine check_corners(conn, nnode, status, nproblem, element_ids)
    integer, intent(in) :: conn(:,:)                 !< (nvert, nelem) corners
    integer, intent(in) :: nnode                     !< number of nodes
    type(status_t), intent(inout) :: status          !< problems appended
    integer, intent(inout) :: nproblem               !< problems so far
    integer, intent(in), optional :: element_ids(:)  !< user ids for messages
    integer :: e, i, j
    do e = 1, size(conn, 2)
      if (any(conn(:, e) < 1) .or. any(conn(:, e) > nnode)) then
        call add_problem(status, nproblem,  &
            element_name(e, element_ids)//' has a node index outside 1..'//int_text(nnode))
        cycle
      end if
      do i = 1, size(conn, 1) - 1
        do j = i + 1, size(conn, 1)
          if (conn(i, e) == conn(j, e)) then
            call add_problem(status, nproblem,  &
                element_name(e, element_ids)//' repeats node '//int_text(conn(i, e)))
          end if
        end do
      end do
    end do
  end subroutine check_corners

  !> The number of smoothing domains (distinct edges/faces) smoothing_domains_build would make
  !> of a mesh, without building them (cells_build sizes its arrays with it): the sides grouped
  !> as the build groups them. A mesh the build rejects (bad corners, a side of three
  !> elements) gets the upper bound nvert x nelem.
  integer function smoothing_domains_count(conn, nnode) result(ndomain)
    integer, intent(in) :: conn(:,:)                 !< (nvert, nelem) corners
    integer, intent(in) :: nnode                     !< number of nodes
    integer, allocatable :: side_group(:)
    type(status_t) :: status
    integer :: nproblem
    ndomain = size(conn)
    nproblem = 0
    call check_corners(conn, nnode, status, nproblem)
    if (nproblem > 0) return
    call group_sides(conn, side_group, ndomain, status, nproblem)
    if (nproblem > 0) ndomain = size(conn)
  end function smoothing_domains_count

  !> Group the element sides (side s = (e-1)*nvert + k) into edges/faces: side_group(s) is
  !> the group of side s, groups numbered in sorted order of their node tuples. Reports sides
  !> shared by more than two elements and pairs that share a side with the same orientation.
  subroutine group_sides(conn, side_group, ngroup, status, nproblem, element_ids)
    integer, intent(in) :: conn(:,:)                 !< (nvert, nelem) valid corners
    integer, allocatable, intent(out) :: side_group(:) !< (nvert*nelem) group of each side
    integer, intent(out) :: ngroup                   !< number of groups (edges/faces)
    type(status_t), intent(inout) :: status          !< problems appended
    integer, intent(inout) :: nproblem               !< problems so far
    integer, intent(in), optional :: element_ids(:)  !< user ids for messages
    integer, allocatable :: key(:,:), order(:)
    integer :: nvert, nside, nsn, nnode, i, j, s
    character(len=:), allocatable :: names

    nvert = size(conn, 1)
    nsn = nvert - 1
    nside = nvert*size(conn, 2)
    nnode = 0
    if (size(conn) > 0) nnode = maxval(conn)
    allocate(key(nsn, nside))
    do s = 1, nside
      call side_tuple(conn, s, key(:, s))
      call sort_small(key(:, s))
    end do
    call radix_sort_tuples(key, nnode, order)

    allocate(side_group(nside))
    ngroup = 0
    i = 1
    do while (i <= nside)
      j = i
      do while (j < nside)
        if (any(key(:, order(j + 1)) /= key(:, order(i)))) exit
        j = j + 1
      end do
      ngroup = ngroup + 1
      side_group(order(i:j)) = ngroup
      if (j - i + 1 > 2) then
        names = element_name(side_element(order(i), nvert), element_ids)
        do s = i + 1, j
          names = names//', '//element_name(side_element(order(s), nvert), element_ids)
        end do
        call add_problem(status, nproblem,  &
            trim(merge('edge', 'face', nvert == 3))//' (nodes '// &
            tuple_text(key(:, order(i)))//') is shared by '//int_text(j - i + 1)// &
            ' elements: '//names)
      else if (j == i + 1) then
        if (side_parity(conn, order(i)) .eqv. side_parity(conn, order(j))) &
          call add_problem(status, nproblem,  &
            element_name(side_element(order(i), nvert), element_ids)//' and '// &
            element_name(side_element(order(j), nvert), element_ids)//' share '// &
            trim(merge('edge', 'face', nvert == 3))//' (nodes '// &
            tuple_text(key(:, order(i)))//') with the same orientation '// &
            '(duplicated, folded or inconsistently oriented elements)')
      end if
      i = j + 1
    end do
  end subroutine group_sides

  !> Number the groups as domains in order of first appearance over (element, local side)
  !> and fill the adjacency arrays and domain_nodes (`lean`: domain_elem, domain_local and
  !> nboundary only).
  subroutine number_domains(conn, side_group, ngroup, domains, lean)
    integer, intent(in) :: conn(:,:)                 !< (nvert, nelem) corners
    integer, intent(in) :: side_group(:)             !< (nvert*nelem) group of each side
    integer, intent(in) :: ngroup                    !< number of groups
    type(smoothing_domains_t), intent(inout) :: domains !< adjacency filled
    logical, intent(in) :: lean                      !< the cells' arrays only
    integer, allocatable :: group_domain(:)
    integer :: nvert, e, k, s, m, nb

    nvert = domains%nvert
    domains%ndomain = ngroup
    allocate(group_domain(ngroup))
    group_domain = 0
    allocate(domains%domain_elem(2, ngroup), domains%domain_local(2, ngroup))
    if (.not. lean) allocate(domains%elem_domain(nvert, domains%nelem), &
                             domains%domain_nodes(domains%nside_nodes, ngroup))
    domains%domain_elem = 0
    domains%domain_local = 0
    m = 0
    s = 0
    do e = 1, domains%nelem
      do k = 1, nvert
        s = s + 1
        if (group_domain(side_group(s)) == 0) then
          m = m + 1
          group_domain(side_group(s)) = m
          domains%domain_elem(1, m) = e
          domains%domain_local(1, m) = k
          if (lean) cycle
          call side_tuple(conn, s, domains%domain_nodes(:, m))
          domains%elem_domain(k, e) = m
        else
          domains%domain_elem(2, group_domain(side_group(s))) = e
          domains%domain_local(2, group_domain(side_group(s))) = k
          if (.not. lean) domains%elem_domain(k, e) = group_domain(side_group(s))
        end if
      end do
    end do

    domains%nboundary = count(domains%domain_elem(2, :) == 0)
    if (lean) return
    allocate(domains%is_boundary(ngroup))
    domains%is_boundary = domains%domain_elem(2, :) == 0
    allocate(domains%boundary_list(domains%nboundary))
    nb = 0
    do m = 1, ngroup
      if (domains%is_boundary(m)) then
        nb = nb + 1
        domains%boundary_list(nb) = m
      end if
    end do
  end subroutine number_domains

  !> Stable least-significant-digit radix sort of integer tuples key(:, s), entries in
  !> 1..nnode: order(1:n) lists the tuples lexicographically ascending (ties by position).
  subroutine radix_sort_tuples(key, nnode, order)
    integer, intent(in) :: key(:,:)                  !< (width, n) tuples
    integer, intent(in) :: nnode                     !< largest possible entry
    integer, allocatable, intent(out) :: order(:)    !< (n) sorted positions
    integer, allocatable :: next_slot(:), sorted(:), spare(:)
    integer :: n, pass, i, s, v, total, c

    n = size(key, 2)
    allocate(order(n), sorted(n), next_slot(nnode))
    order = [(i, i = 1, n)]
    do pass = size(key, 1), 1, -1
      next_slot = 0
      do s = 1, n
        next_slot(key(pass, s)) = next_slot(key(pass, s)) + 1
      end do
      total = 0
      do v = 1, nnode
        c = next_slot(v)
        next_slot(v) = total + 1
        total = total + c
      end do
      do i = 1, n
        s = order(i)
        v = key(pass, s)
        sorted(next_slot(v)) = s
        next_slot(v) = next_slot(v) + 1
      end do
      call move_alloc(order, spare)
      call move_alloc(sorted, order)
      call move_alloc(spare, sorted)
    end do
  end subroutine radix_sort_tuples

  !> Measure, altitudes, inward unit normals (z = 0 in 2D) and side measures of a triangle
  !> (3 corners, x-y plane) or a tetrahedron (4 corners) of corner coordinates xc, sides
  !> numbered as TRIANGLE_EDGE_CORNERS / TETRAHEDRON_FACE_CORNERS.
  pure subroutine simplex_geometry(xc, measure, altitude, normal, side)
    real(wp), intent(in) :: xc(:,:)           !< (>= 2 or 3, 3 or 4) corner coordinates
    real(wp), intent(out) :: measure          !< signed area or volume
    real(wp), intent(out) :: altitude(:)      !< (3 or 4) altitude over side k
    real(wp), intent(out) :: normal(:,:)      !< (3, 3 or 4) unit inward normal of side k
    real(wp), intent(out) :: side(:)          !< (3 or 4) length or area of side k
    if (size(xc, 2) == 3) then
      call triangle_geometry(xc(1:2, 1:3), measure, altitude(1:3), normal(:, 1:3), side(1:3))
    else
      call tetrahedron_geometry(xc(1:3, 1:4), measure, altitude(1:4), normal(:, 1:4), &
                                side(1:4))
    end if
  end subroutine simplex_geometry

  !> Area, altitudes, inward normals and edge lengths of a triangle in the x-y plane.
  pure subroutine triangle_geometry(xc, area, altitude, normal, length)
    real(wp), intent(in) :: xc(2, 3)          !< corner coordinates
    real(wp), intent(out) :: area             !< signed area (positive counter-clockwise)
    real(wp), intent(out) :: altitude(3)      !< altitude over edge k
    real(wp), intent(out) :: normal(3, 3)     !< unit inward normal of edge k (z = 0)
    real(wp), intent(out) :: length(3)        !< length of edge k
    real(wp) :: t(2)
    integer :: k
    area = 0.5_wp*((xc(1, 2) - xc(1, 1))*(xc(2, 3) - xc(2, 1)) &
                 - (xc(2, 2) - xc(2, 1))*(xc(1, 3) - xc(1, 1)))
    do k = 1, 3
      t = xc(:, TRIANGLE_EDGE_CORNERS(2, k)) - xc(:, TRIANGLE_EDGE_CORNERS(1, k))
      length(k) = norm2(t)
      if (length(k) > 0.0_wp) then
        normal(:, k) = [-t(2), t(1), 0.0_wp]/length(k)
        altitude(k) = 2.0_wp*area/length(k)
      else
        normal(:, k) = 0.0_wp
        altitude(k) = 0.0_wp
      end if
    end do
  end subroutine triangle_geometry

  !> Volume, altitudes, inward normals and face areas of a tetrahedron.
  pure subroutine tetrahedron_geometry(xc, volume, altitude, normal, area)
    real(wp), intent(in) :: xc(3, 4)          !< corner coordinates
    real(wp), intent(out) :: volume           !< signed volume (positive when well oriented)
    real(wp), intent(out) :: altitude(4)      !< altitude over face k
    real(wp), intent(out) :: normal(3, 4)     !< unit inward normal of face k
    real(wp), intent(out) :: area(4)          !< area of face k
    real(wp) :: outward(3), a(3)
    integer :: k
    volume = dot_product(cross(xc(:, 2) - xc(:, 1), xc(:, 3) - xc(:, 1)), &
                         xc(:, 4) - xc(:, 1))/6.0_wp
    do k = 1, 4
      a = xc(:, TETRAHEDRON_FACE_CORNERS(1, k))
      outward = 0.5_wp*cross(xc(:, TETRAHEDRON_FACE_CORNERS(2, k)) - a, &
                             xc(:, TETRAHEDRON_FACE_CORNERS(3, k)) - a)
      area(k) = norm2(outward)
      if (area(k) > 0.0_wp) then
        normal(:, k) = -outward/area(k)
        altitude(k) = 3.0_wp*volume/area(k)
      else
        normal(:, k) = 0.0_wp
        altitude(k) = 0.0_wp
      end if
    end do
  end subroutine tetrahedron_geometry


  !> Corners of side s = (e-1)*nvert + k in the element's outward order.
  pure subroutine side_tuple(conn, s, tuple)
    integer, intent(in) :: conn(:,:)          !< (nvert, nelem) corners
    integer, intent(in) :: s                  !< side index
    integer, intent(out) :: tuple(:)          !< (nvert-1) corner nodes
    integer :: e, k
    e = side_element(s, size(conn, 1))
    k = s - (e - 1)*size(conn, 1)
    if (size(conn, 1) == 3) then
      tuple = conn(TRIANGLE_EDGE_CORNERS(:, k), e)
    else
      tuple = conn(TETRAHEDRON_FACE_CORNERS(:, k), e)
    end if
  end subroutine side_tuple

  !> Element of side s.
  pure integer function side_element(s, nvert)
    integer, intent(in) :: s                  !< side index (e-1)*nvert + k
    integer, intent(in) :: nvert              !< corners per element
    side_element = (s - 1)/nvert + 1
  end function side_element

  !> Parity of the permutation that sorts the outward-ordered corners of side s (true = odd).
  !> Two elements with consistent orientation see a shared side with opposite parities.
  pure logical function side_parity(conn, s)
    integer, intent(in) :: conn(:,:)          !< (nvert, nelem) corners
    integer, intent(in) :: s                  !< side index
    integer :: t(size(conn, 1) - 1), i, j, inversions
    call side_tuple(conn, s, t)
    inversions = 0
    do i = 1, size(t) - 1
      do j = i + 1, size(t)
        if (t(i) > t(j)) inversions = inversions + 1
      end do
    end do
    side_parity = mod(inversions, 2) == 1
  end function side_parity

  !> Append one problem to status (the first MAX_REPORTED are spelled out).
  subroutine add_problem(status, nproblem, text)
    type(status_t), intent(inout) :: status   !< set to failed
    integer, intent(inout) :: nproblem        !< problems so far, incremented
    character(len=*), intent(in) :: text      !< the problem
    nproblem = nproblem + 1
    status%ok = .false.
    if (nproblem == 1) then
      status%message = 'smoothing domains: '//text
    else if (nproblem <= MAX_REPORTED) then
      status%message = status%message//'; '//text
    end if
  end subroutine add_problem

  !> Add the total count when more problems were found than spelled out.
  subroutine close_report(status, nproblem)
    type(status_t), intent(inout) :: status   !< message completed
    integer, intent(in) :: nproblem           !< problems found
    if (nproblem > MAX_REPORTED) status%message = status%message//'; ... ('// &
        int_text(nproblem)//' problems in all)'
  end subroutine close_report

  !> "element <id>" with the user id when given, else the 1-based index.
  function element_name(e, element_ids) result(text)
    integer, intent(in) :: e                         !< element index
    integer, intent(in), optional :: element_ids(:)  !< user ids
    character(len=:), allocatable :: text
    if (present(element_ids)) then
      text = 'element '//int_text(element_ids(e))
    else
      text = 'element '//int_text(e)
    end if
  end function element_name

  !> Integers separated by blanks.
  function tuple_text(t) result(text)
    integer, intent(in) :: t(:)               !< the integers
    character(len=:), allocatable :: text
    integer :: i
    text = int_text(t(1))
    do i = 2, size(t)
      text = text//' '//int_text(t(i))
    end do
  end function tuple_text

  !> Integer as text without blanks.
  function int_text(i) result(text)
    integer, intent(in) :: i                  !< the integer
    character(len=:), allocatable :: text
    character(len=24) :: buffer
    write(buffer, '(i0)') i
    text = trim(buffer)
  end function int_text

  !> Real as short text.
  function real_text(r) result(text)
    real(wp), intent(in) :: r                 !< the number
    character(len=:), allocatable :: text
    character(len=24) :: buffer
    write(buffer, '(es12.4)') r
    text = trim(adjustl(buffer))
  end function real_text

end module mefem_smoothing_domains
