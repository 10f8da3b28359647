!> Smoothing domains (edges/faces) of structured triangle and tetrahedron meshes: counts by
!> Euler's formula, adjacency both ways, outward boundary orientation, geometry against
!> direct formulas, invariance under node perturbation, error reports for invalid meshes.
!> With MEFEM_BENCH=1 it also times the build for about 1e6 tetrahedra and prints the memory.
! ranks: 1
program test_smoothing_domains
  use mefem_kinds, only: wp, i8
  use mefem_errors, only: status_t
  use mefem_smoothing_domains, only: smoothing_domains_t, smoothing_domains_build, &
      smoothing_domains_count, TRIANGLE_EDGE_CORNERS, TETRAHEDRON_FACE_CORNERS, &
      simplex_geometry
  use mefem_testing, only: test_start, test_finish, check, check_close, check_equal
  implicit none

  character(len=8) :: bench

  call test_start('smoothing_domains')
  call test_triangles(7, 4, 3.5_wp, 2.0_wp)
  call test_triangles(1, 1, 1.0_wp, 1.0_wp)
  call test_tetrahedra(4, 3, 2, 2.0_wp, 1.5_wp, 1.0_wp)
  call test_tetrahedra(1, 1, 1, 1.0_wp, 1.0_wp, 1.0_wp)
  call test_errors()
  call get_environment_variable('MEFEM_BENCH', bench)
  if (trim(bench) == '1') call benchmark(55)
  call test_finish()

contains

  ! ------------------------------------------------------------------ meshes

  !> Rectangle [0,lx] x [0,ly] of nx x ny squares, two counter-clockwise triangles each.
  subroutine make_triangle_mesh(nx, ny, lx, ly, conn, x)
    integer, intent(in) :: nx, ny                    !< squares per direction
    real(wp), intent(in) :: lx, ly                   !< rectangle size
    integer, allocatable, intent(out) :: conn(:,:)   !< (3, 2*nx*ny) corners
    real(wp), allocatable, intent(out) :: x(:,:)     !< (3, nnode) coordinates
    integer :: i, j, a, e
    allocate(x(3, (nx + 1)*(ny + 1)), conn(3, 2*nx*ny))
    do j = 0, ny
      do i = 0, nx
        x(:, j*(nx + 1) + i + 1) = [lx*i/nx, ly*j/ny, 0.0_wp]
      end do
    end do
    e = 0
    do j = 0, ny - 1
      do i = 0, nx - 1
        a = j*(nx + 1) + i + 1
        conn(:, e + 1) = [a, a + 1, a + nx + 2]
        conn(:, e + 2) = [a, a + nx + 2, a + nx + 1]
        e = e + 2
      end do
    end do
  end subroutine make_triangle_mesh

  !> Box [0,lx] x [0,ly] x [0,lz] of nx x ny x nz cubes, each split into 6 tetrahedra along
  !> its main diagonal (Kuhn), every one positively oriented.
  subroutine make_tetrahedron_mesh(nx, ny, nz, lx, ly, lz, conn, x)
    integer, intent(in) :: nx, ny, nz                !< cubes per direction
    real(wp), intent(in) :: lx, ly, lz               !< box size
    integer, allocatable, intent(out) :: conn(:,:)   !< (4, 6*nx*ny*nz) corners
    real(wp), allocatable, intent(out) :: x(:,:)     !< (3, nnode) coordinates
    integer, parameter :: paths(3, 6) = reshape([1, 2, 3,  1, 3, 2,  2, 1, 3,  2, 3, 1, &
                                                 3, 1, 2,  3, 2, 1], [3, 6])
    integer :: i, j, k, t, e, step(3), c(3), v(4), swap
    allocate(x(3, (nx + 1)*(ny + 1)*(nz + 1)), conn(4, 6*nx*ny*nz))
    do k = 0, nz
      do j = 0, ny
        do i = 0, nx
          x(:, lattice_node(nx, ny, i, j, k)) = [lx*i/nx, ly*j/ny, lz*k/nz]
        end do
      end do
    end do
    e = 0
    do k = 0, nz - 1
      do j = 0, ny - 1
        do i = 0, nx - 1
          do t = 1, 6
            c = [i, j, k]
            v(1) = lattice_node(nx, ny, c(1), c(2), c(3))
            step = 0
            step(paths(1, t)) = 1
            c = c + step
            v(2) = lattice_node(nx, ny, c(1), c(2), c(3))
            step = 0
            step(paths(2, t)) = 1
            c = c + step
            v(3) = lattice_node(nx, ny, c(1), c(2), c(3))
            v(4) = lattice_node(nx, ny, i + 1, j + 1, k + 1)
            if (signed_volume(x(:, v)) < 0.0_wp) then
              swap = v(2)
              v(2) = v(3)
              v(3) = swap
            end if
            e = e + 1
            conn(:, e) = v
          end do
        end do
      end do
    end do
  end subroutine make_tetrahedron_mesh

  !> Node index of lattice point (i, j, k) of an nx x ny x nz box.
  pure integer function lattice_node(nx, ny, i, j, k)
    integer, intent(in) :: nx, ny                    !< cubes in x and y
    integer, intent(in) :: i, j, k                   !< lattice coordinates
    lattice_node = (k*(ny + 1) + j)*(nx + 1) + i + 1
  end function lattice_node

  !> Move every node not on the boundary of the box [0,l] by up to amplitude per coordinate.
  subroutine perturb_interior(x, l, amplitude)
    real(wp), intent(inout) :: x(:,:)                !< coordinates
    real(wp), intent(in) :: l(:)                     !< box size per used coordinate
    real(wp), intent(in) :: amplitude                !< largest move per coordinate
    integer :: n, d
    integer(i8) :: seed
    logical :: inside
    seed = 20240611_i8
    do n = 1, size(x, 2)
      inside = .true.
      do d = 1, size(l)
        if (abs(x(d, n)) < 1.0e-12_wp .or. abs(x(d, n) - l(d)) < 1.0e-12_wp) inside = .false.
      end do
      if (.not. inside) cycle
      do d = 1, size(l)
        x(d, n) = x(d, n) + amplitude*(2.0_wp*uniform(seed) - 1.0_wp)
      end do
    end do
  end subroutine perturb_interior

  !> Deterministic uniform number in [0,1) (linear congruential generator, 48 bits).
  real(wp) function uniform(seed)
    integer(i8), intent(inout) :: seed               !< generator state
    seed = modulo(seed*25214903917_i8 + 11_i8, 281474976710656_i8)
    uniform = real(seed, wp)/281474976710656.0_wp
  end function uniform

  ! ------------------------------------------------------------------ geometry helpers

  !> Signed volume of a tetrahedron.
  pure real(wp) function signed_volume(xc)
    real(wp), intent(in) :: xc(3, 4)                 !< corners
    signed_volume = dot_product(cross(xc(:, 2) - xc(:, 1), xc(:, 3) - xc(:, 1)), &
                                xc(:, 4) - xc(:, 1))/6.0_wp
  end function signed_volume

  !> Cross product.
  pure function cross(a, b) result(c)
    real(wp), intent(in) :: a(3), b(3)               !< factors
    real(wp) :: c(3)
    c = [a(2)*b(3) - a(3)*b(2), a(3)*b(1) - a(1)*b(3), a(1)*b(2) - a(2)*b(1)]
  end function cross

  !> Right-hand area vector of a side given by its ordered corners: (t_y, -t_x)*... in 2D
  !> (length = edge length), half the cross product in 3D.
  pure function side_vector(xs) result(s)
    real(wp), intent(in) :: xs(:,:)                  !< (3, 2 or 3) corners in order
    real(wp) :: s(3), t(3)
    if (size(xs, 2) == 2) then
      t = xs(:, 2) - xs(:, 1)
      s = [t(2), -t(1), 0.0_wp]
    else
      s = 0.5_wp*cross(xs(:, 2) - xs(:, 1), xs(:, 3) - xs(:, 1))
    end if
  end function side_vector

  !> Nodes of local side k of element e in the element's outward order.
  function local_side(conn, e, k) result(nodes)
    integer, intent(in) :: conn(:,:), e, k           !< mesh, element, local side
    integer, allocatable :: nodes(:)
    if (size(conn, 1) == 3) then
      nodes = conn(TRIANGLE_EDGE_CORNERS(:, k), e)
    else
      nodes = conn(TETRAHEDRON_FACE_CORNERS(:, k), e)
    end if
  end function local_side

  !> Sorted copy of a short tuple.
  pure function sorted(t) result(s)
    integer, intent(in) :: t(:)                      !< tuple
    integer :: s(size(t)), i, j, v
    s = t
    do i = 2, size(s)
      do j = i, 2, -1
        if (s(j - 1) <= s(j)) exit
        v = s(j)
        s(j) = s(j - 1)
        s(j - 1) = v
      end do
    end do
  end function sorted

  ! ------------------------------------------------------------------ shared checks

  !> Adjacency consistent both ways, side nodes right, orientation from element 1 to 2 (or
  !> out of the body), and for a few elements the altitude and inward normal by direct
  !> formulas; the gradients n_k/H_k of the barycentric coordinates reproduce linear fields.
  subroutine check_common(what, conn, x, d)
    character(len=*), intent(in) :: what             !< label
    integer, intent(in) :: conn(:,:)                 !< corners
    real(wp), intent(in) :: x(:,:)                   !< coordinates
    type(smoothing_domains_t), intent(in) :: d       !< domains to check
    integer :: e, k, m, j, nvert, nsn, bad_link, bad_nodes, bad_orient, nb, eo
    real(wp) :: s(3), centroid(3, 2), worst_grad, g(3, 3), xc(3, 4), foot(3), direct_n(3)
    real(wp) :: direct_h, worst_n, worst_h, tangent(3), t2(3)
    integer, allocatable :: nodes(:)

    nvert = size(conn, 1)
    nsn = nvert - 1
    bad_link = 0
    do e = 1, size(conn, 2)
      do k = 1, nvert
        m = d%elem_domain(k, e)
        if (m < 1 .or. m > d%ndomain) then
          bad_link = bad_link + 1
        else if (.not. ((d%domain_elem(1, m) == e .and. d%domain_local(1, m) == k) .or. &
                        (d%domain_elem(2, m) == e .and. d%domain_local(2, m) == k))) then
          bad_link = bad_link + 1
        end if
      end do
    end do
    call check_equal(bad_link, 0, what//': elem_domain -> domain_elem/domain_local')

    bad_link = 0
    bad_nodes = 0
    bad_orient = 0
    nb = 0
    do m = 1, d%ndomain
      do j = 1, 2
        e = d%domain_elem(j, m)
        if (e == 0) cycle
        if (d%elem_domain(d%domain_local(j, m), e) /= m) bad_link = bad_link + 1
        nodes = local_side(conn, e, d%domain_local(j, m))
        if (any(sorted(nodes) /= sorted(d%domain_nodes(:, m)))) bad_nodes = bad_nodes + 1
        centroid(:, j) = sum(x(:, conn(:, e)), dim=2)/nvert
      end do
      if (d%domain_elem(1, m) < 1) bad_link = bad_link + 1
      if (d%domain_elem(2, m) /= 0 .and. d%domain_elem(2, m) <= d%domain_elem(1, m)) &
        bad_link = bad_link + 1
      if (d%is_boundary(m) .neqv. d%domain_elem(2, m) == 0) bad_link = bad_link + 1
      if (d%is_boundary(m)) nb = nb + 1
      ! right-hand normal of domain_nodes points away from element 1 (toward element 2)
      s = side_vector(x(:, d%domain_nodes(:, m)))
      if (dot_product(s, sum(x(:, d%domain_nodes(:, m)), dim=2)/nsn - centroid(:, 1)) <= 0) &
        bad_orient = bad_orient + 1
      if (.not. d%is_boundary(m)) then
        if (dot_product(s, centroid(:, 2) - centroid(:, 1)) <= 0) bad_orient = bad_orient + 1
      end if
    end do
    call check_equal(bad_link, 0, what//': domain_elem -> elem_domain, elements ascending')
    call check_equal(bad_nodes, 0, what//': domain_nodes are the corners of the side')
    call check_equal(bad_orient, 0, what//': domain_nodes normal points out of element 1')
    call check_equal(d%nboundary, nb, what//': nboundary = count(is_boundary)')
    call check(size(d%boundary_list) == nb, what//': boundary_list size')
    if (size(d%boundary_list) == nb .and. nb > 0) &
      call check(all(d%is_boundary(d%boundary_list)) .and. &
                 all(d%boundary_list(2:) > d%boundary_list(:nb - 1)), &
                 what//': boundary_list ascending boundary domains')

    ! gradients of barycentric coordinates: grad N_k = n_k/H_k; sum = 0, sum x_k grad N_k = I
    worst_grad = 0.0_wp
    do e = 1, size(conn, 2)
      g = 0.0_wp
      s = 0.0_wp
      do k = 1, nvert
        s = s + d%inward_normal(:, k, e)/d%altitude(k, e)
        do j = 1, 3
          g(:, j) = g(:, j) + x(:, conn(k, e))*d%inward_normal(j, k, e)/d%altitude(k, e)
        end do
      end do
      do j = 1, nsn
        g(j, j) = g(j, j) - 1.0_wp
      end do
      worst_grad = max(worst_grad, maxval(abs(g(1:nsn, 1:nsn))), maxval(abs(s)))
    end do
    call check(worst_grad < 1.0e-10_wp, what//': sum grad N = 0 and sum x grad N = I')

    ! direct formulas on a few elements: foot of the altitude from corner k on side k
    worst_n = 0.0_wp
    worst_h = 0.0_wp
    do eo = 0, 2
      e = 1 + eo*(size(conn, 2) - 1)/2
      xc(:, 1:nvert) = x(:, conn(:, e))
      do k = 1, nvert
        nodes = local_side(conn, e, k)
        tangent = x(:, nodes(2)) - x(:, nodes(1))
        foot = x(:, nodes(1)) + dot_product(xc(:, k) - x(:, nodes(1)), tangent)* &
            tangent/dot_product(tangent, tangent)
        if (nvert == 4) then
          ! project onto the plane: remove the in-plane part along the second direction
          t2 = x(:, nodes(3)) - foot
          t2 = t2 - dot_product(t2, tangent)*tangent/dot_product(tangent, tangent)
          foot = foot + dot_product(xc(:, k) - foot, t2)*t2/dot_product(t2, t2)
        end if
        direct_h = norm2(xc(:, k) - foot)
        direct_n = (xc(:, k) - foot)/direct_h
        worst_h = max(worst_h, abs(direct_h - d%altitude(k, e))/direct_h)
        worst_n = max(worst_n, maxval(abs(direct_n - d%inward_normal(:, k, e))))
      end do
    end do
    call check(worst_h < 1.0e-12_wp, what//': altitudes match the distance to the side')
    call check(worst_n < 1.0e-12_wp, what//': inward normals match the direct formula')
  end subroutine check_common

  !> Same topology (numbering, adjacency, node order) in two builds.
  subroutine check_same_topology(what, a, b)
    character(len=*), intent(in) :: what             !< label
    type(smoothing_domains_t), intent(in) :: a, b    !< the two builds
    logical :: same
    same = a%ndomain == b%ndomain .and. a%nboundary == b%nboundary
    if (same) same = all(a%domain_elem == b%domain_elem) .and. &
        all(a%domain_local == b%domain_local) .and. all(a%elem_domain == b%elem_domain) &
        .and. all(a%domain_nodes == b%domain_nodes) .and. &
        all(a%is_boundary .eqv. b%is_boundary)
    call check(same, what//': perturbed mesh has the same topology')
  end subroutine check_same_topology

  ! ------------------------------------------------------------------ tests

  !> (1) and (3) in 2D.
  subroutine test_triangles(nx, ny, lx, ly)
    integer, intent(in) :: nx, ny                    !< squares per direction
    real(wp), intent(in) :: lx, ly                   !< rectangle size
    integer, allocatable :: conn(:,:)
    real(wp), allocatable :: x(:,:)
    type(smoothing_domains_t) :: d, dp
    type(status_t) :: status
    character(len=40) :: what
    integer :: m, n_two
    real(wp) :: perimeter, divergence, xm(3)

    write(what, '(a,i0,a,i0)') 'triangles ', nx, 'x', ny
    call make_triangle_mesh(nx, ny, lx, ly, conn, x)
    call smoothing_domains_build(conn, x, d, status)
    call check(status%ok, trim(what)//': build succeeds')
    if (.not. status%ok) return
    call check_equal(d%ndim, 2, trim(what)//': ndim')
    call check_equal(d%ndomain, 3*nx*ny + nx + ny, trim(what)//': edges = 3 nx ny + nx + ny')
    call check_equal(smoothing_domains_count(conn, size(x, 2)), d%ndomain, &
                     trim(what)//': smoothing_domains_count = the domains built')
    call check_equal(d%ndomain, size(x, 2) + size(conn, 2) - 1, &
                     trim(what)//': Euler E = V + F - 1')
    call check_equal(d%nboundary, 2*(nx + ny), trim(what)//': boundary edges = 2(nx+ny)')
    n_two = count(d%domain_elem(1, :) > 0 .and. d%domain_elem(2, :) > 0)
    call check_equal(n_two, d%ndomain - d%nboundary, trim(what)//': interior edges have 2 elements')
    call check_close(sum(d%domain_weight), lx*ly, 1.0e-13_wp, trim(what)//': sum A_m = area')
    call check_close(sum(d%elem_measure), lx*ly, 1.0e-13_wp, trim(what)//': sum A_e = area')
    perimeter = 0.0_wp
    divergence = 0.0_wp
    do m = 1, d%ndomain
      if (.not. d%is_boundary(m)) cycle
      perimeter = perimeter + d%side_measure(m)
      xm = sum(x(:, d%domain_nodes(:, m)), dim=2)/2.0_wp
      divergence = divergence + dot_product(xm, side_vector(x(:, d%domain_nodes(:, m))))/2.0_wp
    end do
    call check_close(perimeter, 2.0_wp*(lx + ly), 1.0e-13_wp, &
                     trim(what)//': boundary edges cover the perimeter')
    call check_close(divergence, lx*ly, 1.0e-13_wp, &
                     trim(what)//': outward boundary edges enclose the area (divergence)')
    ! one element by hand: first triangle (0,0), (hx,0), (hx,hy); edge 3 = nodes 1-2 at y=0
    call check_close(d%altitude(3, 1), ly/ny, 1.0e-13_wp, trim(what)//': altitude over y=0')
    call check_close(d%inward_normal(:, 3, 1), [0.0_wp, 1.0_wp, 0.0_wp], 0.0_wp, &
                     trim(what)//': inward normal over y=0', atol=1.0e-14_wp)
    call check_close(d%altitude(1, 1), lx/nx, 1.0e-13_wp, trim(what)//': altitude over x=hx')
    call check_close(d%inward_normal(:, 1, 1), [-1.0_wp, 0.0_wp, 0.0_wp], 0.0_wp, &
                     trim(what)//': inward normal over x=hx', atol=1.0e-14_wp)
    call check_common(trim(what), conn, x, d)

    ! (3) interior nodes moved by up to 15% of the spacing: orientation kept
    call perturb_interior(x, [lx, ly], 0.15_wp*min(lx/nx, ly/ny))
    call smoothing_domains_build(conn, x, dp, status)
    call check(status%ok, trim(what)//': perturbed build succeeds')
    if (.not. status%ok) return
    call check_same_topology(trim(what), d, dp)
    call check_close(sum(dp%domain_weight), lx*ly, 1.0e-13_wp, &
                     trim(what)//' perturbed: sum A_m = area')
    call check_common(trim(what)//' perturbed', conn, x, dp)
    call check_lean(trim(what)//' perturbed', conn, x, dp)
  end subroutine test_triangles

  !> (2) and (3) in 3D.
  subroutine test_tetrahedra(nx, ny, nz, lx, ly, lz)
    integer, intent(in) :: nx, ny, nz                !< cubes per direction
    real(wp), intent(in) :: lx, ly, lz               !< box size
    integer, allocatable :: conn(:,:)
    real(wp), allocatable :: x(:,:)
    type(smoothing_domains_t) :: d, dp
    type(status_t) :: status
    character(len=40) :: what
    integer :: m, nedge, nbox_faces, i, j, k
    real(wp) :: surface, divergence, closure(3), xm(3), s(3), volume

    write(what, '(a,i0,a,i0,a,i0)') 'tetrahedra ', nx, 'x', ny, 'x', nz
    call make_tetrahedron_mesh(nx, ny, nz, lx, ly, lz, conn, x)
    volume = lx*ly*lz
    call smoothing_domains_build(conn, x, d, status)
    call check(status%ok, trim(what)//': build succeeds')
    if (.not. status%ok) return
    call check_equal(d%ndim, 3, trim(what)//': ndim')
    call check_equal(smoothing_domains_count(conn, size(x, 2)), d%ndomain, &
                     trim(what)//': smoothing_domains_count = the domains built')
    nbox_faces = 2*(nx*ny + ny*nz + nx*nz)
    call check_equal(d%nboundary, 2*nbox_faces, trim(what)//': boundary faces = 2 x squares')
    call check_equal(4*size(conn, 2), 2*(d%ndomain - d%nboundary) + d%nboundary, &
                     trim(what)//': 4T = 2 F_int + F_bnd')
    ! Euler for a ball: V - E + F - T = 1, edges of the Kuhn lattice counted per direction
    nedge = 0
    do k = 0, 1
      do j = 0, 1
        do i = 0, 1
          if (i + j + k == 0) cycle
          nedge = nedge + (nx + 1 - i)*(ny + 1 - j)*(nz + 1 - k)
        end do
      end do
    end do
    call check_equal(size(x, 2) - nedge + d%ndomain - size(conn, 2), 1, &
                     trim(what)//': Euler V - E + F - T = 1')
    call check_equal(count(d%domain_elem(2, :) > 0), d%ndomain - d%nboundary, &
                     trim(what)//': interior faces have 2 elements')
    call check_close(sum(d%domain_weight), volume, 1.0e-13_wp, trim(what)//': sum V_m = volume')
    surface = 0.0_wp
    divergence = 0.0_wp
    closure = 0.0_wp
    do m = 1, d%ndomain
      if (.not. d%is_boundary(m)) cycle
      surface = surface + d%side_measure(m)
      s = side_vector(x(:, d%domain_nodes(:, m)))
      closure = closure + s
      xm = sum(x(:, d%domain_nodes(:, m)), dim=2)/3.0_wp
      divergence = divergence + dot_product(xm, s)/3.0_wp
    end do
    call check_close(surface, 2.0_wp*(lx*ly + ly*lz + lx*lz), 1.0e-13_wp, &
                     trim(what)//': boundary face areas = box surface')
    call check(maxval(abs(closure)) < 1.0e-13_wp, trim(what)//': boundary surface is closed')
    call check_close(divergence, volume, 1.0e-13_wp, &
                     trim(what)//': outward boundary faces enclose the volume (divergence)')
    call check_common(trim(what), conn, x, d)

    ! (3) interior nodes moved by up to 10% of the spacing: orientation kept
    call perturb_interior(x, [lx, ly, lz], 0.1_wp*min(lx/nx, ly/ny, lz/nz))
    call smoothing_domains_build(conn, x, dp, status)
    call check(status%ok, trim(what)//': perturbed build succeeds')
    if (.not. status%ok) return
    call check_same_topology(trim(what), d, dp)
    call check_close(sum(dp%domain_weight), volume, 1.0e-13_wp, &
                     trim(what)//' perturbed: sum V_m = volume')
    call check_common(trim(what)//' perturbed', conn, x, dp)
    call check_lean(trim(what)//' perturbed', conn, x, dp)
  end subroutine test_tetrahedra

  !> The lean build (the cells' arrays only) gives the full build's adjacency, boundary
  !> count, element measures and domain weights, and simplex_geometry the full build's
  !> altitudes and normals, to the bit.
  subroutine check_lean(what, conn, x, full)
    character(len=*), intent(in) :: what          !< case label
    integer, intent(in) :: conn(:,:)              !< (nvert, nelem) corners
    real(wp), intent(in) :: x(:,:)                !< (3, nnode) coordinates
    type(smoothing_domains_t), intent(in) :: full !< the full build
    type(smoothing_domains_t) :: lean
    type(status_t) :: status
    real(wp) :: measure, altitude(4), normal(3, 4), side(4)
    integer :: e, nv
    logical :: same
    call smoothing_domains_build(conn, x, lean, status, lean=.true.)
    call check(status%ok, what//': lean build succeeds')
    if (.not. status%ok) return
    call check(.not. (allocated(lean%inward_normal) .or. allocated(lean%altitude) .or. &
                      allocated(lean%elem_domain) .or. allocated(lean%domain_nodes)), &
               what//': lean build keeps no normals, altitudes or side lists')
    same = lean%ndomain == full%ndomain .and. lean%nboundary == full%nboundary
    if (same) same = all(lean%domain_elem == full%domain_elem) .and. &
                     all(lean%domain_local == full%domain_local) .and. &
                     all(lean%elem_measure == full%elem_measure) .and. &
                     all(lean%domain_weight == full%domain_weight)
    call check(same, what//': lean build = full build (adjacency, measures, weights)')
    nv = size(conn, 1)
    do e = 1, size(conn, 2)
      call simplex_geometry(x(:, conn(:, e)), measure, altitude(1:nv), normal(:, 1:nv), &
                            side(1:nv))
      same = same .and. measure == full%elem_measure(e) .and. &
             all(altitude(1:nv) == full%altitude(:, e)) .and. &
             all(normal(:, 1:nv) == full%inward_normal(:, :, e))
    end do
    call check(same, what//': simplex_geometry = the full build''s element geometry')
  end subroutine check_lean

  !> (4) invalid meshes are reported through status with the elements named.
  subroutine test_errors()
    integer, allocatable :: conn(:,:), bad(:,:), ids(:)
    real(wp), allocatable :: x(:,:)
    type(smoothing_domains_t) :: d
    type(status_t) :: status
    integer :: n, e

    call make_triangle_mesh(3, 2, 3.0_wp, 2.0_wp, conn, x)
    n = size(conn, 2)

    ! duplicated element (the last one again)
    bad = reshape([conn, conn(:, n)], [3, n + 1])
    call smoothing_domains_build(bad, x, d, status)
    call check(.not. status%ok, 'duplicated triangle: status not ok')
    call check(has(status, 'element '//itoa(n)//' and element '//itoa(n + 1)) .and. &
               has(status, 'same orientation'), 'duplicated triangle: both elements named', &
               message(status))

    ! the same with user ids
    ids = [(1000 + e, e = 1, n + 1)]
    call smoothing_domains_build(bad, x, d, status, element_ids=ids)
    call check(has(status, 'element '//itoa(1000 + n)//' and element '//itoa(1001 + n)), &
               'duplicated triangle: user ids named', message(status))

    ! an edge shared by three elements: a third triangle on the diagonal of square 1
    ! (element 1 = 1-2-6, element 2 = 1-6-5; the new node 14 at (-1, 2) is left of 1 -> 6)
    x = reshape([x, [-1.0_wp, 2.0_wp, 0.0_wp]], [3, size(x, 2) + 1])
    bad = reshape([conn, [1, 6, size(x, 2)]], [3, n + 1])
    call smoothing_domains_build(bad, x, d, status)
    call check(.not. status%ok .and. has(status, 'shared by 3 elements: element 1, element 2, '// &
               'element '//itoa(n + 1)), 'edge of three triangles: reported', message(status))
    call check_equal(smoothing_domains_count(bad, size(x, 2)), 3*(n + 1), &
                     'edge of three triangles: smoothing_domains_count gives the upper bound')

    ! one element turned over (clockwise among counter-clockwise neighbours)
    bad = conn
    bad(:, 2) = conn([1, 3, 2], 2)
    call smoothing_domains_build(bad, x, d, status)
    call check(.not. status%ok .and. has(status, 'element 2'), &
               'turned-over triangle: reported', message(status))

    ! a lone clockwise triangle: topology fine, negative area
    call smoothing_domains_build(reshape([1, 5, 2], [3, 1]), x, d, status)
    call check(.not. status%ok .and. has(status, 'element 1 has a non-positive area'), &
               'clockwise triangle: negative area reported', message(status))

    ! node index out of range and a repeated corner
    bad = conn
    bad(2, 3) = size(x, 2) + 7
    bad(3, 5) = bad(1, 5)
    call smoothing_domains_build(bad, x, d, status)
    call check(.not. status%ok .and. has(status, 'element 3 has a node index outside') .and. &
               has(status, 'element 5 repeats node'), 'bad corners: both reported', &
               message(status))

    ! duplicated tetrahedron
    call make_tetrahedron_mesh(2, 2, 2, 1.0_wp, 1.0_wp, 1.0_wp, conn, x)
    n = size(conn, 2)
    bad = reshape([conn(:, 1:7), conn(:, 7), conn(:, 8:n)], [4, n + 1])
    call smoothing_domains_build(bad, x, d, status)
    call check(.not. status%ok .and. has(status, 'element 7') .and. &
               has(status, 'element 8') .and. has(status, 'face'), &
               'duplicated tetrahedron: reported', message(status))
    ! many problems: the count is given
    bad = reshape([conn, conn], [4, 2*n])
    call smoothing_domains_build(bad, x, d, status)
    call check(.not. status%ok .and. has(status, 'problems in all'), &
               'whole mesh duplicated: problems counted', message(status))
  end subroutine test_errors

  !> Does the status message contain text?
  logical function has(status, text)
    type(status_t), intent(in) :: status             !< a build result
    character(len=*), intent(in) :: text             !< expected part of the message
    has = .false.
    if (allocated(status%message)) has = index(status%message, text) > 0
  end function has

  !> The status message (or a placeholder).
  function message(status) result(text)
    type(status_t), intent(in) :: status             !< a build result
    character(len=:), allocatable :: text
    text = 'no message'
    if (allocated(status%message)) text = status%message(1:min(len(status%message), 600))
  end function message

  !> Integer as text.
  function itoa(i) result(text)
    integer, intent(in) :: i                         !< the integer
    character(len=:), allocatable :: text
    character(len=16) :: buffer
    write(buffer, '(i0)') i
    text = trim(buffer)
  end function itoa

  ! ------------------------------------------------------------------ benchmark

  !> Build the domains of an n^3-cube box x 6 tetrahedra; print time and memory.
  subroutine benchmark(n)
    integer, intent(in) :: n                         !< cubes per side
    integer, allocatable :: conn(:,:)
    real(wp), allocatable :: x(:,:)
    type(smoothing_domains_t) :: d
    type(status_t) :: status
    integer(i8) :: t0, t1, rate, rss_before, peak_after, rss_after
    character(len=200) :: line

    call make_tetrahedron_mesh(n, n, n, 1.0_wp, 1.0_wp, 1.0_wp, conn, x)
    rss_before = proc_status_kb('VmRSS:')
    call reset_peak()
    call system_clock(t0, rate)
    call smoothing_domains_build(conn, x, d, status)
    call system_clock(t1)
    peak_after = proc_status_kb('VmHWM:')
    rss_after = proc_status_kb('VmRSS:')
    call check(status%ok .and. d%ndomain == 12*n**3 + 6*n**2, 'benchmark: faces = 12n^3 + 6n^2')
    write(line, '(a,i0,a,i0,a,i0,a,f8.3,a)') 'BENCH smoothing_domains: ', size(conn, 2), &
        ' tets, ', size(x, 2), ' nodes, ', d%ndomain, ' faces: build ', &
        real(t1 - t0, wp)/real(rate, wp), ' s'
    write(*, '(a)') trim(line)
    write(line, '(a,f8.1,a,f8.1,a,f8.1,a)') 'BENCH smoothing_domains: RSS before ', &
        rss_before/1024.0_wp, ' MiB, after ', rss_after/1024.0_wp, ' MiB, peak ', &
        peak_after/1024.0_wp, ' MiB (peak since build start if the kernel allows reset)'
    write(*, '(a)') trim(line)
  end subroutine benchmark

  !> A field of /proc/self/status in kB (0 when not available).
  integer(i8) function proc_status_kb(field)
    character(len=*), intent(in) :: field            !< e.g. 'VmHWM:'
    character(len=200) :: line
    integer :: unit, ios
    proc_status_kb = 0
    open(newunit=unit, file='/proc/self/status', status='old', action='read', iostat=ios)
    if (ios /= 0) return
    do
      read(unit, '(a)', iostat=ios) line
      if (ios /= 0) exit
      if (index(line, field) == 1) then
        read(line(len(field) + 1:), *, iostat=ios) proc_status_kb
        exit
      end if
    end do
    close(unit)
  end function proc_status_kb

  !> Reset the peak resident size (Linux: write 5 to /proc/self/clear_refs); ignore failure.
  subroutine reset_peak()
    integer :: unit, ios
    open(newunit=unit, file='/proc/self/clear_refs', status='old', action='write', iostat=ios)
    if (ios /= 0) return
    write(unit, '(a)', iostat=ios) '5'
    close(unit, iostat=ios)
  end subroutine reset_peak

end program test_smoothing_domains
