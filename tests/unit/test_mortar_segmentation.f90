!> Geometric kernels of mortar contact (mefem_mortar_segmentation):
!> - slave facet inside a larger coplanar master: n_AB = A/12 (1 + delta_AB) (3D),
!>   L/6 (1 + delta_AB) (2D), row sums A/3 (L/2), sum_C n_AC = sum_B n_AB;
!> - n_AC = sum_B n_AB P_BC with P_BC = N_C^m at the point of the master met by the slave
!>   normal through slave node B (N^m o projection is affine, so this holds over any overlap;
!>   P is computed here in 3D by a line-plane intersection, independent of the kernel's frame);
!> - partial overlaps with closed-form polygons (shifted triangle, corner of a square, the
!>   hexagon of a triangle and its point reflection, 2D intervals), against the exact
!>   product rule int_T f g = A/12 (sum f_k g_k + sum f sum g) on a fan from vertex 1;
!> - the mortar patch test: non-matching slave triangles and master triangles/quads (mixed
!>   orientation) covering the same square (segment in 2D): sum_C n_AC x_C = sum_B n_AB x_B
!>   and the same for a linear field, for every slave node; with the master lifted by a gap,
!>   the weighted gap kappa_A n.(sum_C n_AC x_C - sum_B n_AB x_B) equals that gap;
!> - no overlap, touching facets, degenerate slaves, a master seen edge-on: exact zeros;
!> - a gap, a tilt of the master, rigid translation + rotation, reversed or shifted master
!>   numbering leave the weights unchanged; a planar quad agrees with its two triangles
!>   (area, n_AB, sum_C n_AC, sum_C n_AC x_C), a quad with node 4 = node 3 with the triangle;
!> - the overlap tolerance; Sutherland-Hodgman and the shoelace area directly;
!> - timing (BENCH lines: ns per pair).
! ranks: 1
program test_mortar_segmentation
  use mefem_kinds, only: wp, i8
  use mefem_vector_math, only: cross
  use mefem_mortar_segmentation, only: mortar_segment_pair_2d, mortar_triangle_pair_3d, &
      sutherland_hodgman, polygon_signed_area, MAX_POLYGON_VERTICES, OVERLAP_REL_TOL
  use mefem_testing, only: test_start, test_finish, check, check_close
  implicit none

  real(wp), parameter :: PI = acos(-1.0_wp)
  !> Set .true. to print every measured error (used to fill in the comments).
  logical, parameter :: VERBOSE = .false.

  call test_start('mortar_segmentation')
  call test_polygon_helpers()
  call test_inside_coplanar_3d()
  call test_partial_3d()
  call test_no_overlap_and_degenerate_3d()
  call test_orientation_and_quads_3d()
  call test_invariance_3d()
  call test_tolerance_3d()
  call test_patch_3d()
  call test_inside_2d()
  call test_partial_2d()
  call test_degenerate_and_invariance_2d()
  call test_patch_2d()
  call benchmark()
  call test_finish()

contains

  ! ---------------------------------------------------------------------------------------
  ! helpers
  ! ---------------------------------------------------------------------------------------

  !> Pass when err <= tol (NaN fails); the detail shows the measured value.
  subroutine check_small(err, tol, name)
    real(wp), intent(in) :: err, tol        !< measured error, allowed error
    character(len=*), intent(in) :: name    !< what is checked
    character(len=80) :: detail
    write(detail, '(a,es10.3,a,es10.3)') 'error ', err, ' > ', tol
    if (VERBOSE) write(*, '(a,es10.3,a)') 'INFO measured ', err, ' : '//trim(name)
    call check(err <= tol .and. err == err, name, detail)
  end subroutine check_small

  !> Largest absolute entry of a difference.
  pure real(wp) function max_diff(a, b)
    real(wp), intent(in) :: a(:,:), b(:,:)  !< same shape
    max_diff = maxval(abs(a - b))
  end function max_diff

  !> Rotation by angle about a unit axis (Rodrigues).
  pure function rotation(axis, angle) result(r)
    real(wp), intent(in) :: axis(3), angle  !< axis (normalised here), angle in radians
    real(wp) :: r(3, 3), k(3), kx(3, 3)
    integer :: i
    k = axis/norm2(axis)
    kx = reshape([0.0_wp, k(3), -k(2), -k(3), 0.0_wp, k(1), k(2), -k(1), 0.0_wp], [3, 3])
    r = 0.0_wp
    do i = 1, 3
      r(i, i) = 1.0_wp
    end do
    r = r + sin(angle)*kx + (1.0_wp - cos(angle))*matmul(kx, kx)
  end function rotation

  !> Points of the local plane (p, height) placed in space: x = origin + R (p1, p2, height).
  pure function place(p, height, r, origin) result(x)
    real(wp), intent(in) :: p(:,:)            !< local in-plane points (2, n)
    real(wp), intent(in) :: height(:)         !< local height of each point (n)
    real(wp), intent(in) :: r(3, 3), origin(3) !< rotation, translation
    real(wp) :: x(3, size(p, 2))
    integer :: k
    do k = 1, size(p, 2)
      x(:, k) = origin + matmul(r, [p(1, k), p(2, k), height(k)])
    end do
  end function place

  !> Barycentrics of q in a 2D triangle by solving [t2-t1, t3-t1] (l2, l3) = q - t1.
  pure function barycentric_solve(t, q) result(l)
    real(wp), intent(in) :: t(2, 3), q(2)   !< triangle, point
    real(wp) :: l(3), m(2, 2), det, rhs(2)
    m(:, 1) = t(:, 2) - t(:, 1)
    m(:, 2) = t(:, 3) - t(:, 1)
    rhs = q - t(:, 1)
    det = m(1, 1)*m(2, 2) - m(1, 2)*m(2, 1)
    l(2) = (rhs(1)*m(2, 2) - rhs(2)*m(1, 2))/det
    l(3) = (m(1, 1)*rhs(2) - m(2, 1)*rhs(1))/det
    l(1) = 1.0_wp - l(2) - l(3)
  end function barycentric_solve

  !> Exact n_AB, n_AC, area over a convex polygon given in the slave's local 2D coordinates,
  !> for a slave triangle and a master triangle (both local 2D): fan from vertex 1 and
  !> int_T f g = A/12 (sum_k f_k g_k + sum_k f_k sum_k g_k) on each fan triangle.
  subroutine reference_weights(poly, slave, master, n_ab, n_ac, area)
    real(wp), intent(in) :: poly(:,:)              !< overlap polygon (2, n), counter-clockwise
    real(wp), intent(in) :: slave(2, 3), master(2, 3)  !< local triangles
    real(wp), intent(out) :: n_ab(3, 3), n_ac(3, 3), area  !< exact integrals
    real(wp) :: fs(3, 3), fm(3, 3), tri(2, 3), a
    integer :: k, v, i, j
    n_ab = 0.0_wp
    n_ac = 0.0_wp
    area = 0.0_wp
    do k = 2, size(poly, 2) - 1
      tri(:, 1) = poly(:, 1)
      tri(:, 2) = poly(:, k)
      tri(:, 3) = poly(:, k + 1)
      a = 0.5_wp*((tri(1, 2) - tri(1, 1))*(tri(2, 3) - tri(2, 1)) &
          - (tri(2, 2) - tri(2, 1))*(tri(1, 3) - tri(1, 1)))
      area = area + a
      do v = 1, 3
        fs(:, v) = barycentric_solve(slave, tri(:, v))
        fm(:, v) = barycentric_solve(master, tri(:, v))
      end do
      do i = 1, 3
        do j = 1, 3
          n_ab(i, j) = n_ab(i, j) + a/12.0_wp*(sum(fs(i, :)*fs(j, :)) + sum(fs(i, :))*sum(fs(j, :)))
          n_ac(i, j) = n_ac(i, j) + a/12.0_wp*(sum(fs(i, :)*fm(j, :)) + sum(fs(i, :))*sum(fm(j, :)))
        end do
      end do
    end do
  end subroutine reference_weights

  !> P(B, C) = barycentric C of the point where the line x_B + t n meets the plane of the
  !> master triangle, computed in 3D (sub-triangle area vectors projected on the master normal).
  function projection_matrix_3d(xs, xm) result(p)
    real(wp), intent(in) :: xs(3, 3), xm(3, 3)   !< slave and master triangles
    real(wp) :: p(3, 3), n(3), nm(3), y(3), t
    integer :: b
    n = cross(xs(:, 2) - xs(:, 1), xs(:, 3) - xs(:, 1))
    n = n/norm2(n)
    nm = cross(xm(:, 2) - xm(:, 1), xm(:, 3) - xm(:, 1))
    do b = 1, 3
      t = dot_product(xm(:, 1) - xs(:, b), nm)/dot_product(n, nm)
      y = xs(:, b) + t*n
      p(b, 1) = dot_product(cross(xm(:, 2) - y, xm(:, 3) - y), nm)/dot_product(nm, nm)
      p(b, 2) = dot_product(cross(xm(:, 3) - y, xm(:, 1) - y), nm)/dot_product(nm, nm)
      p(b, 3) = dot_product(cross(xm(:, 1) - y, xm(:, 2) - y), nm)/dot_product(nm, nm)
    end do
  end function projection_matrix_3d

  ! ---------------------------------------------------------------------------------------
  ! 3D
  ! ---------------------------------------------------------------------------------------

  !> Sutherland-Hodgman on a square clipped by a triangle, full containment, disjoint, and the
  !> refusal of oversize input; the shoelace area with either orientation.
  subroutine test_polygon_helpers()
    real(wp) :: square(2, 4), tri(2, 3), result(2, MAX_POLYGON_VERTICES), big(2, 12)
    integer :: n
    square = reshape([0.0_wp, 0.0_wp, 1.0_wp, 0.0_wp, 1.0_wp, 1.0_wp, 0.0_wp, 1.0_wp], [2, 4])
    call check_close(polygon_signed_area(4, square), 1.0_wp, 1.0e-15_wp, 'shoelace: unit square')
    call check_close(polygon_signed_area(4, square(:, [4, 3, 2, 1])), -1.0_wp, 1.0e-15_wp, &
        'shoelace: clockwise square is negative')
    ! The triangle (-0.5,-1), (1,0.5), (-0.5,2) (edges on y = x - 0.5, x + y = 1.5, x = -0.5)
    ! cuts off the corners (1,0) and (1,1) with legs 0.5: the pentagon (0,0), (0.5,0),
    ! (1,0.5), (0.5,1), (0,1) of area 1 - 2/8 = 0.75.
    tri = reshape([-0.5_wp, -1.0_wp, 1.0_wp, 0.5_wp, -0.5_wp, 2.0_wp], [2, 3])
    call sutherland_hodgman(4, square, 3, tri, n, result)
    call check(n >= 5 .and. n <= 7, 'sutherland_hodgman: square by triangle gives a pentagon')
    call check_close(polygon_signed_area(n, result), 0.75_wp, 1.0e-15_wp, &
        'sutherland_hodgman: clipped area 0.75')
    call sutherland_hodgman(4, square(:, [4, 3, 2, 1]), 3, tri, n, result)
    call check_close(polygon_signed_area(n, result), -0.75_wp, 1.0e-15_wp, &
        'sutherland_hodgman: clockwise subject keeps its orientation')
    tri = reshape([-5.0_wp, -5.0_wp, 5.0_wp, -5.0_wp, 0.0_wp, 5.0_wp], [2, 3])
    call sutherland_hodgman(4, square, 3, tri, n, result)
    call check(n == 4 .and. max_diff(result(:, 1:4), square) == 0.0_wp, &
        'sutherland_hodgman: subject inside the clip polygon is returned unchanged')
    tri = reshape([2.0_wp, 0.0_wp, 3.0_wp, 0.0_wp, 2.0_wp, 1.0_wp], [2, 3])
    call sutherland_hodgman(4, square, 3, tri, n, result)
    call check(n == 0, 'sutherland_hodgman: disjoint polygons give n = 0')
    big = 0.0_wp
    call sutherland_hodgman(12, big, 12, big, n, result)
    call check(n == -1, 'sutherland_hodgman: refuses more than MAX_POLYGON_VERTICES')
  end subroutine test_polygon_helpers

  !> Slave triangle inside a larger coplanar master triangle and quad, in a tilted plane.
  subroutine test_inside_coplanar_3d()
    real(wp) :: r(3, 3), origin(3), xs(3, 3), xm(3, 4), n_ab(3, 3), n_ac(3, 4), overlap
    real(wp) :: want(3, 3), area, p(3, 3), slave_p(2, 3), master_p(2, 4), moment_s(3)
    real(wp) :: moment_m(3)
    integer :: a
    r = rotation([0.3_wp, -0.5_wp, 0.8_wp], 0.9_wp)
    origin = [1.5_wp, -0.7_wp, 2.2_wp]
    slave_p = reshape([0.1_wp, 0.2_wp, 0.9_wp, 0.35_wp, 0.3_wp, 0.8_wp], [2, 3])
    xs = place(slave_p, [0.0_wp, 0.0_wp, 0.0_wp], r, origin)
    area = 0.5_wp*abs((0.9_wp - 0.1_wp)*(0.8_wp - 0.2_wp) - (0.35_wp - 0.2_wp)*(0.3_wp - 0.1_wp))
    want = area/12.0_wp
    do a = 1, 3
      want(a, a) = area/6.0_wp
    end do
    master_p = reshape([-1.0_wp, -1.0_wp, 3.0_wp, -0.5_wp, 0.2_wp, 2.5_wp, 0.0_wp, 0.0_wp], [2, 4])
    xm = 0.0_wp
    xm(:, 1:3) = place(master_p(:, 1:3), [0.0_wp, 0.0_wp, 0.0_wp], r, origin)
    call mortar_triangle_pair_3d(xs, xm, 3, n_ab, n_ac, overlap)
    ! measured: n_ab 3.5e-17 (entries ~0.01-0.02), n_ac vs n_ab P 6.9e-18
    call check_close(overlap, area, 1.0e-13_wp, 'inside 3D tri: overlap = slave area')
    call check_small(max_diff(n_ab, want), 1.0e-13_wp*area, &
        'inside 3D tri: n_AB = A/12 (1 + delta_AB)')
    call check_close(sum(n_ab, dim=2), [area, area, area]/3.0_wp, 1.0e-13_wp, &
        'inside 3D tri: sum_B n_AB = A/3')
    call check_close(sum(n_ac, dim=2), sum(n_ab, dim=2), 1.0e-13_wp, &
        'inside 3D tri: sum_C n_AC = sum_B n_AB')
    call check(all(n_ac(:, 4) == 0.0_wp), 'inside 3D tri: column 4 of n_AC is zero')
    p = projection_matrix_3d(xs, xm(:, 1:3))
    call check_small(max_diff(n_ac(:, 1:3), matmul(n_ab, p)), 1.0e-13_wp*area, &
        'inside 3D tri: n_AC = n_AB P (master functions at the slave nodes)')

    ! A large planar (non-parallelogram) quad around the slave.
    master_p = reshape([-1.0_wp, -1.2_wp, 2.6_wp, -0.6_wp, 2.0_wp, 2.4_wp, -0.8_wp, 1.9_wp], &
        [2, 4])
    xm = place(master_p, [0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp], r, origin)
    call mortar_triangle_pair_3d(xs, xm, 4, n_ab, n_ac, overlap)
    call check_close(overlap, area, 1.0e-13_wp, 'inside 3D quad: overlap = slave area')
    call check_small(max_diff(n_ab, want), 1.0e-13_wp*area, &
        'inside 3D quad: n_AB = A/12 (1 + delta_AB)')
    call check_close(sum(n_ac, dim=2), sum(n_ab, dim=2), 1.0e-13_wp, &
        'inside 3D quad: sum_C n_AC = sum_B n_AB')
    do a = 1, 3
      moment_m = matmul(xm, n_ac(a, :))
      moment_s = matmul(xs, n_ab(a, :))
      ! measured <= 2.8e-17
      call check_small(maxval(abs(moment_m - moment_s)), 1.0e-14_wp, &
          'inside 3D quad: sum_C n_AC x_C = sum_B n_AB x_B (pallets reproduce linear fields)')
    end do
  end subroutine test_inside_coplanar_3d

  !> Partial overlaps with known polygons, the master lifted by a gap and tilted.
  subroutine test_partial_3d()
    real(wp) :: slave(2, 3), master(2, 3), hexagon(2, 6), corner(2, 3), sliver(2, 3)
    real(wp) :: square(2, 4)
    slave = reshape([0.0_wp, 0.0_wp, 1.0_wp, 0.0_wp, 0.0_wp, 1.0_wp], [2, 3])
    ! Master = slave shifted by (0.2, 0): overlap triangle (0.2,0), (1,0), (0.2,0.8), area 0.32.
    master = slave + spread([0.2_wp, 0.0_wp], 2, 3)
    sliver = reshape([0.2_wp, 0.0_wp, 1.0_wp, 0.0_wp, 0.2_wp, 0.8_wp], [2, 3])
    call partial_case(slave, master, sliver, 0.32_wp, 'shifted triangle')
    ! Master = point reflection of the slave about its centroid: a hexagon through the edge
    ! trisection points, area 2/3 of the slave's (1/3).
    master = 2.0_wp/3.0_wp - slave
    hexagon = reshape([1.0_wp, 0.0_wp, 2.0_wp, 0.0_wp, 2.0_wp, 1.0_wp, 1.0_wp, 2.0_wp, &
        0.0_wp, 2.0_wp, 0.0_wp, 1.0_wp], [2, 6])/3.0_wp
    call partial_case(slave, master, hexagon, 1.0_wp/3.0_wp, 'hexagon (reflected triangle)')
    ! Slave (0,0), (2,0), (0,2) and the master square [1,3] x [-1,1] given as the triangle
    ! (1,-1), (3,-1), (1,3), which covers the same part: the triangle (1,0), (2,0), (1,1).
    slave = 2.0_wp*slave
    master = reshape([1.0_wp, -1.0_wp, 3.0_wp, -1.0_wp, 1.0_wp, 3.0_wp], [2, 3])
    corner = reshape([1.0_wp, 0.0_wp, 2.0_wp, 0.0_wp, 1.0_wp, 1.0_wp], [2, 3])
    call partial_case(slave, master, corner, 0.5_wp, 'corner of a larger triangle')
    ! The square itself as a quad: area and n_AB of the same corner.
    square = reshape([1.0_wp, -1.0_wp, 3.0_wp, -1.0_wp, 3.0_wp, 1.0_wp, 1.0_wp, 1.0_wp], [2, 4])
    call partial_quad_case(slave, square, corner, 0.5_wp)
  end subroutine test_partial_3d

  !> One partial-overlap case: slave and master triangles in local 2D, exact polygon and area.
  !> Placed in a tilted plane; the master flat (coplanar), lifted by +-gap and tilted.
  subroutine partial_case(slave, master, poly, area, name)
    real(wp), intent(in) :: slave(2, 3), master(2, 3)   !< local triangles
    real(wp), intent(in) :: poly(:,:)                   !< exact overlap polygon (ccw)
    real(wp), intent(in) :: area                        !< exact overlap area
    character(len=*), intent(in) :: name                !< label
    real(wp) :: r(3, 3), origin(3), xs(3, 3), xm(3, 4), n_ab(3, 3), n_ac(3, 4), overlap
    real(wp) :: ref_ab(3, 3), ref_ac(3, 3), ref_area, heights(3, 4), p(3, 3)
    integer :: h
    character(len=20), parameter :: LIFT(4) = [character(len=20) :: 'coplanar', 'gap +0.3', &
        'penetration -0.2', 'tilted']
    call reference_weights(poly, slave, master, ref_ab, ref_ac, ref_area)
    call check_close(ref_area, area, 1.0e-14_wp, 'partial 3D '//name//': reference polygon area')
    r = rotation([-0.2_wp, 0.7_wp, 0.4_wp], 2.1_wp)
    origin = [-3.0_wp, 0.5_wp, 1.25_wp]
    heights(:, 1) = 0.0_wp
    heights(:, 2) = 0.3_wp
    heights(:, 3) = -0.2_wp
    heights(:, 4) = [0.1_wp, -0.4_wp, 0.7_wp]
    xs = place(slave, [0.0_wp, 0.0_wp, 0.0_wp], r, origin)
    do h = 1, 4
      xm = 0.0_wp
      xm(:, 1:3) = place(master, heights(:, h), r, origin)
      call mortar_triangle_pair_3d(xs, xm, 3, n_ab, n_ac, overlap)
      ! measured: n_ab <= 6.9e-17, n_ac <= 5.6e-17, n_ac vs n_ab P <= 5.6e-17
      ! (entries ~0.003-0.05)
      call check_close(overlap, area, 1.0e-13_wp, 'partial 3D '//name//', '// &
          trim(LIFT(h))//': overlap area')
      call check_small(max_diff(n_ab, ref_ab), 1.0e-14_wp, 'partial 3D '//name//', '// &
          trim(LIFT(h))//': n_AB exact')
      call check_small(max_diff(n_ac(:, 1:3), ref_ac), 1.0e-14_wp, 'partial 3D '//name// &
          ', '//trim(LIFT(h))//': n_AC exact')
      p = projection_matrix_3d(xs, xm(:, 1:3))
      call check_small(max_diff(n_ac(:, 1:3), matmul(n_ab, p)), 1.0e-13_wp, 'partial 3D '// &
          name//', '//trim(LIFT(h))//': n_AC = n_AB P (3D line-plane intersection)')
    end do
  end subroutine partial_case

  !> A master quad cutting a corner of the slave: area and n_AB exact, row sums of n_AC.
  subroutine partial_quad_case(slave, square, poly, area)
    real(wp), intent(in) :: slave(2, 3), square(2, 4)   !< local slave triangle, master quad
    real(wp), intent(in) :: poly(:,:)                   !< exact overlap polygon (ccw)
    real(wp), intent(in) :: area                        !< exact overlap area
    real(wp) :: r(3, 3), origin(3), xs(3, 3), xm(3, 4), n_ab(3, 3), n_ac(3, 4), overlap
    real(wp) :: ref_ab(3, 3), ref_ac(3, 3), ref_area
    call reference_weights(poly, slave, slave, ref_ab, ref_ac, ref_area)
    r = rotation([0.9_wp, 0.1_wp, -0.3_wp], -0.6_wp)
    origin = [0.25_wp, 4.0_wp, -1.0_wp]
    xs = place(slave, [0.0_wp, 0.0_wp, 0.0_wp], r, origin)
    xm = place(square, [0.5_wp, 0.5_wp, 0.5_wp, 0.5_wp], r, origin)
    call mortar_triangle_pair_3d(xs, xm, 4, n_ab, n_ac, overlap)
    ! measured: n_ab 5.6e-17
    call check_close(overlap, area, 1.0e-13_wp, 'partial 3D quad corner: overlap area')
    call check_small(max_diff(n_ab, ref_ab), 1.0e-14_wp, 'partial 3D quad corner: n_AB exact')
    call check_close(sum(n_ac, dim=2), sum(ref_ab, dim=2), 1.0e-13_wp, &
        'partial 3D quad corner: sum_C n_AC = sum_B n_AB')
  end subroutine partial_quad_case

  !> Disjoint and touching facets, degenerate slaves, a master seen edge-on, invalid nm.
  subroutine test_no_overlap_and_degenerate_3d()
    real(wp) :: xs(3, 3), xm(3, 4), n_ab(3, 3), n_ac(3, 4), overlap
    xs = reshape([0.0_wp, 0.0_wp, 0.0_wp, 1.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 1.0_wp, 0.0_wp], [3, 3])
    xm = 0.0_wp
    ! disjoint (bounding boxes overlap: the master lies beyond the hypotenuse)
    xm(:, 1:3) = reshape([0.6_wp, 0.6_wp, 0.1_wp, 1.5_wp, 0.6_wp, 0.1_wp, 0.6_wp, 1.5_wp, &
        0.1_wp], [3, 3])
    call mortar_triangle_pair_3d(xs, xm, 3, n_ab, n_ac, overlap)
    call check(all(n_ab == 0.0_wp) .and. all(n_ac == 0.0_wp) .and. overlap == 0.0_wp, &
        'no overlap 3D: beyond the hypotenuse gives exact zeros')
    ! touching at a vertex (master = slave shifted by (0.5,0.5): one common point)
    xm(:, 1:3) = xs + spread([0.5_wp, 0.5_wp, 0.0_wp], 2, 3)
    call mortar_triangle_pair_3d(xs, xm, 3, n_ab, n_ac, overlap)
    call check(all(n_ab == 0.0_wp) .and. all(n_ac == 0.0_wp) .and. overlap == 0.0_wp, &
        'no overlap 3D: touching at a point gives exact zeros')
    ! sharing an edge from the other side (the slave mirrored across the hypotenuse)
    xm(:, 1:3) = reshape([1.0_wp, 1.0_wp, 0.0_wp, 0.0_wp, 1.0_wp, 0.0_wp, 1.0_wp, 0.0_wp, &
        0.0_wp], [3, 3])
    call mortar_triangle_pair_3d(xs, xm, 3, n_ab, n_ac, overlap)
    call check(all(n_ab == 0.0_wp) .and. all(n_ac == 0.0_wp) .and. overlap == 0.0_wp, &
        'no overlap 3D: neighbour across a common edge gives exact zeros')
    ! far away
    xm(:, 1:3) = xs + spread([10.0_wp, 0.0_wp, 0.0_wp], 2, 3)
    call mortar_triangle_pair_3d(xs, xm, 3, n_ab, n_ac, overlap)
    call check(all(n_ab == 0.0_wp) .and. overlap == 0.0_wp, 'no overlap 3D: far master')
    ! degenerate slaves against a master that covers them
    xm(:, 1:3) = reshape([-5.0_wp, -5.0_wp, 0.0_wp, 5.0_wp, -5.0_wp, 0.0_wp, 0.0_wp, 5.0_wp, &
        0.0_wp], [3, 3])
    call mortar_triangle_pair_3d(reshape([0.0_wp, 0.0_wp, 0.0_wp, 1.0_wp, 1.0_wp, 0.0_wp, &
        2.0_wp, 2.0_wp, 0.0_wp], [3, 3]), xm, 3, n_ab, n_ac, overlap)
    call check(all(n_ab == 0.0_wp) .and. all(n_ac == 0.0_wp) .and. overlap == 0.0_wp, &
        'degenerate 3D: collinear slave gives zeros')
    call mortar_triangle_pair_3d(spread([0.3_wp, 0.1_wp, 0.0_wp], 2, 3), xm, 3, n_ab, n_ac, &
        overlap)
    call check(all(n_ab == 0.0_wp) .and. all(n_ac == 0.0_wp) .and. overlap == 0.0_wp, &
        'degenerate 3D: slave collapsed to a point gives zeros')
    ! master perpendicular to the slave plane, straddling the slave
    xm(:, 1:3) = reshape([0.3_wp, -1.0_wp, -1.0_wp, 0.3_wp, 2.0_wp, -1.0_wp, 0.3_wp, 0.5_wp, &
        2.0_wp], [3, 3])
    call mortar_triangle_pair_3d(xs, xm, 3, n_ab, n_ac, overlap)
    call check(all(n_ab == 0.0_wp) .and. all(n_ac == 0.0_wp) .and. overlap == 0.0_wp, &
        'degenerate 3D: master seen edge-on gives zeros')
    xm(:, 1:3) = xs
    call mortar_triangle_pair_3d(xs, xm, 5, n_ab, n_ac, overlap)
    call check(all(n_ab == 0.0_wp) .and. overlap == 0.0_wp, 'invalid nm = 5 gives zeros')
  end subroutine test_no_overlap_and_degenerate_3d

  !> Reversed and shifted master numbering; a planar quad against its two triangles (both
  !> diagonals) and a quad with node 4 = node 3 against the triangle.
  subroutine test_orientation_and_quads_3d()
    real(wp) :: r(3, 3), origin(3), xs(3, 3), xm(3, 4), xq(3, 4), n_ab(3, 3), n_ac(3, 4)
    real(wp) :: ab2(3, 3), ac2(3, 4), ab_sum(3, 3), ac_sum(3, 4), overlap, overlap2, area_sum
    real(wp) :: slave(2, 3), quad(2, 4)
    integer :: split, t, perm(4)
    integer, parameter :: HALVES(3, 2, 2) = reshape([1, 2, 3, 1, 3, 4, 1, 2, 4, 2, 3, 4], &
        [3, 2, 2])
    r = rotation([1.0_wp, 1.0_wp, 0.2_wp], 0.45_wp)
    origin = [2.0_wp, 3.0_wp, -4.0_wp]
    slave = reshape([0.1_wp, 0.05_wp, 1.1_wp, 0.3_wp, 0.4_wp, 1.2_wp], [2, 3])
    xs = place(slave, [0.0_wp, 0.0_wp, 0.0_wp], r, origin)
    ! master triangle reversed: columns permuted accordingly
    xm = 0.0_wp
    xm(:, 1:3) = place(reshape([0.5_wp, -0.2_wp, 1.6_wp, 0.9_wp, 0.2_wp, 0.9_wp], [2, 3]), &
        [0.1_wp, 0.1_wp, 0.1_wp], r, origin)
    call mortar_triangle_pair_3d(xs, xm, 3, n_ab, n_ac, overlap)
    call mortar_triangle_pair_3d(xs, xm(:, [3, 2, 1, 4]), 3, ab2, ac2, overlap2)
    call check(overlap > 0.05_wp, 'orientation 3D: the test pair overlaps')
    ! measured 1.2e-16 (entries ~0.01-0.1)
    call check_small(abs(overlap2 - overlap) + max_diff(ab2, n_ab) + &
        max_diff(ac2(:, [3, 2, 1]), n_ac(:, 1:3)), 1.0e-14_wp, &
        'orientation 3D: clockwise master triangle gives the same weights')

    ! planar, non-parallelogram quad partly over the slave
    quad = reshape([0.3_wp, -0.3_wp, 1.5_wp, 0.1_wp, 1.2_wp, 0.9_wp, 0.2_wp, 0.7_wp], [2, 4])
    xq = place(quad, [0.2_wp, 0.2_wp, 0.2_wp, 0.2_wp], r, origin)
    call mortar_triangle_pair_3d(xs, xq, 4, n_ab, n_ac, overlap)
    call check(overlap > 0.1_wp .and. overlap < 0.5_wp*0.98_wp, &
        'quad 3D: the test pair overlaps partly')
    perm = [4, 3, 2, 1]
    call mortar_triangle_pair_3d(xs, xq(:, perm), 4, ab2, ac2, overlap2)
    ! measured 1.2e-16
    call check_small(abs(overlap2 - overlap) + max_diff(ab2, n_ab) + &
        max_diff(ac2, n_ac(:, perm)), 1.0e-14_wp, &
        'quad 3D: clockwise numbering gives the same weights (columns permuted)')
    perm = [3, 4, 1, 2]
    call mortar_triangle_pair_3d(xs, xq(:, perm), 4, ab2, ac2, overlap2)
    ! measured 2.1e-17
    call check_small(abs(overlap2 - overlap) + max_diff(ab2, n_ab) + &
        max_diff(ac2, n_ac(:, perm)), 1.0e-14_wp, &
        'quad 3D: numbering started at node 3 gives the same weights (pallets)')
    do split = 1, 2
      ab_sum = 0.0_wp
      ac_sum = 0.0_wp
      area_sum = 0.0_wp
      do t = 1, 2
        xm = 0.0_wp
        xm(:, 1:3) = xq(:, HALVES(:, t, split))
        call mortar_triangle_pair_3d(xs, xm, 3, ab2, ac2, overlap2)
        ab_sum = ab_sum + ab2
        ac_sum(:, HALVES(:, t, split)) = ac_sum(:, HALVES(:, t, split)) + ac2(:, 1:3)
        area_sum = area_sum + overlap2
      end do
      ! measured: n_ab <= 5.6e-17, n_ac row sums <= 5.6e-17, moments <= 3.3e-16
      call check_close(area_sum, overlap, 1.0e-14_wp, 'quad vs two triangles: overlap area')
      call check_small(max_diff(ab_sum, n_ab), 1.0e-14_wp, 'quad vs two triangles: n_AB')
      call check_small(maxval(abs(sum(ac_sum, dim=2) - sum(n_ac, dim=2))), 1.0e-14_wp, &
          'quad vs two triangles: sum_C n_AC')
      call check_small(max_diff(matmul(xq, transpose(ac_sum)), matmul(xq, transpose(n_ac))), &
          1.0e-14_wp, 'quad vs two triangles: sum_C n_AC x_C (pallets reproduce linear fields)')
    end do
    call check(max_diff(ac_sum, n_ac) > 1.0e-3_wp, &
        'quad vs two triangles: individual n_AC differ (pallet vs split interpolation)')
    ! degenerate quad (node 4 = node 3) = the triangle 1, 2, 3
    xq(:, 4) = xq(:, 3)
    call mortar_triangle_pair_3d(xs, xq, 4, n_ab, n_ac, overlap)
    xm = 0.0_wp
    xm(:, 1:3) = xq(:, 1:3)
    call mortar_triangle_pair_3d(xs, xm, 3, ab2, ac2, overlap2)
    ac2(:, 3) = ac2(:, 3) - n_ac(:, 3) - n_ac(:, 4)
    ac2(:, 1:2) = ac2(:, 1:2) - n_ac(:, 1:2)
    ! measured <= 5.2e-17
    call check_small(abs(overlap2 - overlap) + max_diff(ab2, n_ab) + maxval(abs(ac2(:, 1:3))), &
        1.0e-14_wp, 'degenerate quad (n4 = n3) gives the triangle (columns 3 + 4)')
  end subroutine test_orientation_and_quads_3d

  !> Rigid translation + rotation of a partly overlapping, tilted and lifted tri and quad pair.
  subroutine test_invariance_3d()
    real(wp) :: xs(3, 3), xm(3, 4), n_ab(3, 3), n_ac(3, 4), overlap, r(3, 3), shift(3)
    real(wp) :: ab2(3, 3), ac2(3, 4), overlap2
    integer :: nm
    xs = reshape([0.0_wp, 0.0_wp, 0.0_wp, 1.2_wp, 0.1_wp, 0.05_wp, 0.3_wp, 0.9_wp, -0.1_wp], &
        [3, 3])
    xm = reshape([0.4_wp, -0.3_wp, 0.2_wp, 1.3_wp, 0.6_wp, 0.25_wp, 0.2_wp, 1.1_wp, 0.3_wp, &
        -0.2_wp, 0.2_wp, 0.22_wp], [3, 4])
    r = rotation([0.2_wp, -0.9_wp, 0.4_wp], 2.7_wp)
    shift = [12.5_wp, -7.25_wp, 3.0_wp]
    do nm = 3, 4
      call mortar_triangle_pair_3d(xs, xm, nm, n_ab, n_ac, overlap)
      call mortar_triangle_pair_3d(matmul(r, xs) + spread(shift, 2, 3), &
          matmul(r, xm) + spread(shift, 2, 4), nm, ab2, ac2, overlap2)
      call check(overlap > 0.1_wp, 'invariance 3D: the test pair overlaps')
      ! measured <= 5.2e-16 (area ~0.3, translation ~15)
      call check_small(abs(overlap2 - overlap) + max_diff(ab2, n_ab) + max_diff(ac2, n_ac), &
          1.0e-12_wp, 'invariance 3D: rigid motion leaves the weights unchanged')
    end do
  end subroutine test_invariance_3d

  !> A sliver overlap below OVERLAP_REL_TOL x slave area is dropped, a larger one kept.
  subroutine test_tolerance_3d()
    real(wp) :: xs(3, 3), xm(3, 4), n_ab(3, 3), n_ac(3, 4), overlap, delta
    xs = reshape([0.0_wp, 0.0_wp, 0.0_wp, 1.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 1.0_wp, 0.0_wp], [3, 3])
    ! master square x >= 1 - delta: overlap = corner triangle of area delta^2/2 (slave area 1/2)
    delta = 0.5_wp*sqrt(OVERLAP_REL_TOL)
    xm = reshape([1.0_wp - delta, -1.0_wp, 0.0_wp, 3.0_wp, -1.0_wp, 0.0_wp, 3.0_wp, 2.0_wp, &
        0.0_wp, 1.0_wp - delta, 2.0_wp, 0.0_wp], [3, 4])
    call mortar_triangle_pair_3d(xs, xm, 4, n_ab, n_ac, overlap)
    call check(overlap == 0.0_wp .and. all(n_ab == 0.0_wp), &
        'tolerance 3D: overlap of 0.25 x OVERLAP_REL_TOL x area is dropped')
    delta = 1.0e-4_wp
    xm(1, [1, 4]) = 1.0_wp - delta
    call mortar_triangle_pair_3d(xs, xm, 4, n_ab, n_ac, overlap)
    ! measured relative error 2.2e-13 (cancellation in 1 - delta)
    call check_small(abs(overlap/(0.5_wp*delta**2) - 1.0_wp), 1.0e-9_wp, &
        'tolerance 3D: overlap of 1e-8 x area is kept (area delta^2/2)')
  end subroutine test_tolerance_3d

  !> The mortar patch test: a square covered by 18 slave triangles and, differently cut, by
  !> master quads (both orientations) and triangle pairs, in a tilted plane.
  subroutine test_patch_3d()
    integer, parameter :: NS = 16, NMASTER = 16
    real(wp) :: slave_p(2, NS), master_p(2, NMASTER), xs_all(3, NS), xm_all(3, NMASTER)
    real(wp) :: global_ab(NS, NS), global_ac(NS, NMASTER), r(3, 3), origin(3), normal(3)
    real(wp) :: ab0(NS, NS), ac0(NS, NMASTER), weighted(3), field_s(NS), field_m(NMASTER)
    real(wp) :: err_moment, err_field, err_gap, err_same, gap
    integer :: slave_tri(3, 18), master_conn(4, 14), master_nm(14), n_master_facets, lift
    integer :: a
    real(wp), parameter :: GRID_S(4) = [0.0_wp, 0.3_wp, 0.65_wp, 1.0_wp]
    real(wp), parameter :: GRID_M(4) = [0.0_wp, 0.42_wp, 0.77_wp, 1.0_wp]
    real(wp), parameter :: GRID_MY(4) = [0.0_wp, 0.22_wp, 0.61_wp, 1.0_wp]
    real(wp), parameter :: FIELD_GRADIENT(3) = [0.7_wp, -2.1_wp, 0.4_wp], FIELD_0 = 1.3_wp

    call patch_slave_mesh(GRID_S, slave_p, slave_tri)
    call patch_master_mesh(GRID_M, GRID_MY, master_p, master_conn, master_nm, n_master_facets)
    r = rotation([0.4_wp, 0.3_wp, -0.8_wp], 1.1_wp)
    origin = [5.0_wp, -2.0_wp, 0.75_wp]
    normal = r(:, 3)
    xs_all = place(slave_p, [(0.0_wp, a = 1, NS)], r, origin)
    do lift = 1, 2
      gap = merge(0.0_wp, 0.15_wp, lift == 1)
      xm_all = place(master_p, [(gap, a = 1, NMASTER)], r, origin)
      call assemble_patch(xs_all, slave_tri, xm_all, master_conn, master_nm, &
          n_master_facets, global_ab, global_ac)
      if (lift == 1) then
        ab0 = global_ab
        ac0 = global_ac
      end if
      err_moment = 0.0_wp
      err_field = 0.0_wp
      err_gap = 0.0_wp
      field_s = FIELD_0 + matmul(FIELD_GRADIENT, xs_all)
      field_m = FIELD_0 + matmul(FIELD_GRADIENT, xm_all - spread(gap*normal, 2, NMASTER))
      do a = 1, NS
        weighted = matmul(xm_all, global_ac(a, :)) - matmul(xs_all, global_ab(a, :))
        err_gap = max(err_gap, abs(dot_product(normal, weighted)/sum(global_ab(a, :)) - gap))
        weighted = weighted - gap*sum(global_ab(a, :))*normal
        err_moment = max(err_moment, maxval(abs(weighted)))
        err_field = max(err_field, abs(dot_product(global_ac(a, :), field_m) &
            - dot_product(global_ab(a, :), field_s)))
      end do
      if (lift == 1) then
        ! measured: moments 1.1e-16, field 2.2e-16
        call check_close(sum(global_ab), 1.0_wp, 1.0e-13_wp, 'patch 3D: sum n_AB = square area')
        call check_close(sum(global_ac), 1.0_wp, 1.0e-13_wp, 'patch 3D: sum n_AC = square area')
        call check_small(err_moment, 1.0e-12_wp, &
            'patch 3D: sum_C n_AC x_C = sum_B n_AB x_B for every slave node')
        call check_small(err_field, 1.0e-12_wp, &
            'patch 3D: sum_C n_AC f(x_C) = sum_B n_AB f(x_B), f linear')
      else
        ! measured: gap 8.0e-16, moments 1.6e-16, same weights 6.2e-17, field 2.2e-16
        call check_small(err_gap, 1.0e-12_wp, 'patch 3D lifted: weighted gap g_A = gap')
        call check_small(err_moment, 1.0e-12_wp, &
            'patch 3D lifted: sum_C n_AC x_C = sum_B n_AB x_B + gap A_A n')
        err_same = max(max_diff(global_ab, ab0), max_diff(global_ac, ac0))
        call check_small(err_same, 1.0e-14_wp, 'patch 3D lifted: weights equal the coplanar ones')
        call check_small(err_field, 1.0e-12_wp, &
            'patch 3D lifted: linear field transmitted (projected master positions)')
      end if
    end do
  end subroutine test_patch_3d

  !> 4 x 4 slave nodes on grid lines g (interior nodes moved), 18 triangles, alternating
  !> diagonals, counter-clockwise.
  subroutine patch_slave_mesh(g, p, tri)
    real(wp), intent(in) :: g(4)           !< grid lines in x and y
    real(wp), intent(out) :: p(2, 16)      !< node positions
    integer, intent(out) :: tri(3, 18)     !< triangles
    integer :: i, j, n00, n10, n01, n11, t
    do j = 1, 4
      do i = 1, 4
        p(:, i + 4*(j - 1)) = [g(i), g(j)]
      end do
    end do
    p(:, 6) = p(:, 6) + [0.04_wp, -0.03_wp]
    p(:, 11) = p(:, 11) + [-0.05_wp, 0.02_wp]
    t = 0
    do j = 1, 3
      do i = 1, 3
        n00 = i + 4*(j - 1)
        n10 = n00 + 1
        n01 = n00 + 4
        n11 = n01 + 1
        if (mod(i + j, 2) == 0) then
          tri(:, t + 1) = [n00, n10, n11]
          tri(:, t + 2) = [n00, n11, n01]
        else
          tri(:, t + 1) = [n00, n10, n01]
          tri(:, t + 2) = [n10, n11, n01]
        end if
        t = t + 2
      end do
    end do
  end subroutine patch_slave_mesh

  !> 4 x 4 master nodes on grid lines (gx, gy), interior nodes moved; cells alternate between
  !> a quad (counter-clockwise and clockwise in turn) and two triangles (one clockwise).
  subroutine patch_master_mesh(gx, gy, p, conn, nm, n_facets)
    real(wp), intent(in) :: gx(4), gy(4)   !< grid lines
    real(wp), intent(out) :: p(2, 16)      !< node positions
    integer, intent(out) :: conn(4, 14)    !< facets (column 4 unused for triangles)
    integer, intent(out) :: nm(14)         !< 3 or 4
    integer, intent(out) :: n_facets       !< facet count
    integer :: i, j, n00, n10, n01, n11
    do j = 1, 4
      do i = 1, 4
        p(:, i + 4*(j - 1)) = [gx(i), gy(j)]
      end do
    end do
    p(:, 7) = p(:, 7) + [-0.06_wp, 0.05_wp]
    p(:, 10) = p(:, 10) + [0.03_wp, 0.04_wp]
    n_facets = 0
    conn = 0
    do j = 1, 3
      do i = 1, 3
        n00 = i + 4*(j - 1)
        n10 = n00 + 1
        n01 = n00 + 4
        n11 = n01 + 1
        if (mod(i + j, 2) == 0) then
          n_facets = n_facets + 1
          nm(n_facets) = 4
          if (mod(i, 2) == 0) then
            conn(:, n_facets) = [n00, n10, n11, n01]
          else
            conn(:, n_facets) = [n10, n00, n01, n11]
          end if
        else
          nm(n_facets + 1:n_facets + 2) = 3
          conn(1:3, n_facets + 1) = [n00, n10, n01]
          conn(1:3, n_facets + 2) = [n10, n01, n11]
          n_facets = n_facets + 2
        end if
      end do
    end do
  end subroutine patch_master_mesh

  !> Sum the pair weights over all slave triangles x master facets into global matrices.
  subroutine assemble_patch(xs_all, slave_tri, xm_all, master_conn, master_nm, n_master_facets, &
      global_ab, global_ac)
    real(wp), intent(in) :: xs_all(:,:), xm_all(:,:)   !< node positions
    integer, intent(in) :: slave_tri(:,:)              !< slave triangles
    integer, intent(in) :: master_conn(:,:), master_nm(:)  !< master facets
    integer, intent(in) :: n_master_facets             !< master facet count
    real(wp), intent(out) :: global_ab(:,:), global_ac(:,:)  !< assembled weights
    real(wp) :: xm(3, 4), n_ab(3, 3), n_ac(3, 4), overlap
    integer :: s, m, nm
    global_ab = 0.0_wp
    global_ac = 0.0_wp
    do s = 1, size(slave_tri, 2)
      do m = 1, n_master_facets
        nm = master_nm(m)
        xm = 0.0_wp
        xm(:, 1:nm) = xm_all(:, master_conn(1:nm, m))
        call mortar_triangle_pair_3d(xs_all(:, slave_tri(:, s)), xm, nm, n_ab, n_ac, overlap)
        global_ab(slave_tri(:, s), slave_tri(:, s)) = &
            global_ab(slave_tri(:, s), slave_tri(:, s)) + n_ab
        global_ac(slave_tri(:, s), master_conn(1:nm, m)) = &
            global_ac(slave_tri(:, s), master_conn(1:nm, m)) + n_ac(:, 1:nm)
      end do
    end do
  end subroutine assemble_patch

  ! ---------------------------------------------------------------------------------------
  ! 2D
  ! ---------------------------------------------------------------------------------------

  !> Points on a line in the plane: x = origin + s t + h n, n = (t_y, -t_x).
  pure function place_2d(s, h, angle, origin) result(x)
    real(wp), intent(in) :: s(:), h(:)          !< tangential and normal coordinates
    real(wp), intent(in) :: angle, origin(2)    !< direction angle of t, translation
    real(wp) :: x(2, size(s)), t(2)
    integer :: k
    t = [cos(angle), sin(angle)]
    do k = 1, size(s)
      x(:, k) = origin + s(k)*t + h(k)*[t(2), -t(1)]
    end do
  end function place_2d

  !> Slave segment inside a longer collinear (and a tilted) master segment.
  subroutine test_inside_2d()
    real(wp) :: xs(2, 2), xm(2, 2), n_ab(2, 2), n_ac(2, 2), overlap, want(2, 2), length
    real(wp) :: p(2, 2)
    integer :: b
    length = 0.7_wp
    xs = place_2d([0.4_wp, 0.4_wp + length], [0.0_wp, 0.0_wp], 0.6_wp, [1.0_wp, 2.0_wp])
    xm = place_2d([1.6_wp, -0.5_wp], [0.0_wp, 0.0_wp], 0.6_wp, [1.0_wp, 2.0_wp])
    call mortar_segment_pair_2d(xs, xm, n_ab, n_ac, overlap)
    want = length/6.0_wp
    want(1, 1) = length/3.0_wp
    want(2, 2) = length/3.0_wp
    ! measured: n_ab 5.6e-17, n_ac vs n_ab P 2.8e-17, tilted 2.5e-16
    call check_close(overlap, length, 1.0e-13_wp, 'inside 2D: overlap = L')
    call check_small(max_diff(n_ab, want), 1.0e-13_wp*length, 'inside 2D: n_AB = L/6 (1 + delta)')
    call check_close(sum(n_ab, dim=2), [length, length]/2.0_wp, 1.0e-13_wp, &
        'inside 2D: sum_B n_AB = L/2')
    call check_close(sum(n_ac, dim=2), sum(n_ab, dim=2), 1.0e-13_wp, &
        'inside 2D: sum_C n_AC = sum_B n_AB')
    ! master (reversed) from s = 1.6 to -0.5: N_1^m(s) = (s + 0.5)/2.1 at the slave nodes
    do b = 1, 2
      p(b, 1) = (0.4_wp + real(b - 1, wp)*length + 0.5_wp)/2.1_wp
      p(b, 2) = 1.0_wp - p(b, 1)
    end do
    call check_small(max_diff(n_ac, matmul(n_ab, p)), 1.0e-14_wp, 'inside 2D: n_AC = n_AB P')
    ! tilted master, below and above: the normal line through s meets it where its tangential
    ! coordinate is s, whatever its height
    xm = place_2d([1.6_wp, -0.5_wp], [0.3_wp, -0.2_wp], 0.6_wp, [1.0_wp, 2.0_wp])
    call mortar_segment_pair_2d(xs, xm, n_ab, n_ac, overlap)
    call check_small(max_diff(n_ac, matmul(n_ab, p)) + abs(overlap - length), 1.0e-14_wp, &
        'inside 2D: tilted master gives the same weights')
  end subroutine test_inside_2d

  !> Partial interval overlaps against exact antiderivatives.
  subroutine test_partial_2d()
    real(wp) :: xs(2, 2), xm(2, 2), n_ab(2, 2), n_ac(2, 2), overlap, want_ab(2, 2)
    real(wp) :: want_ac(2, 2), lo, hi, m1, m2
    ! slave s in [0, 2], master from s = 1.2 to 3.5: overlap [1.2, 2]
    xs = place_2d([0.0_wp, 2.0_wp], [0.0_wp, 0.0_wp], -0.3_wp, [0.5_wp, 0.5_wp])
    xm = place_2d([1.2_wp, 3.5_wp], [0.1_wp, 0.1_wp], -0.3_wp, [0.5_wp, 0.5_wp])
    call mortar_segment_pair_2d(xs, xm, n_ab, n_ac, overlap)
    lo = 1.2_wp
    hi = 2.0_wp
    m1 = 1.2_wp
    m2 = 3.5_wp
    call exact_interval(lo, hi, 2.0_wp, m1, m2, want_ab, want_ac)
    ! measured: n_ab 1.2e-16, n_ac 2.4e-16, master inside 3.3e-16
    call check_close(overlap, 0.8_wp, 1.0e-13_wp, 'partial 2D: overlap 0.8')
    call check_small(max_diff(n_ab, want_ab), 1.0e-14_wp, 'partial 2D: n_AB exact')
    call check_small(max_diff(n_ac, want_ac), 1.0e-14_wp, 'partial 2D: n_AC exact')
    ! master inside the slave, reversed: overlap [0.5, 1.4]
    xm = place_2d([1.4_wp, 0.5_wp], [-0.2_wp, -0.2_wp], -0.3_wp, [0.5_wp, 0.5_wp])
    call mortar_segment_pair_2d(xs, xm, n_ab, n_ac, overlap)
    call exact_interval(0.5_wp, 1.4_wp, 2.0_wp, 1.4_wp, 0.5_wp, want_ab, want_ac)
    call check_close(overlap, 0.9_wp, 1.0e-13_wp, 'partial 2D: master inside the slave')
    call check_small(max_diff(n_ab, want_ab) + max_diff(n_ac, want_ac), 1.0e-14_wp, &
        'partial 2D: master inside the slave, weights exact')
  end subroutine test_partial_2d

  !> Exact int over [lo, hi] of N_A N_B (slave on [0, length]) and N_A N_C (master from
  !> s = m1 to s = m2), by antiderivatives of the monomials.
  subroutine exact_interval(lo, hi, length, m1, m2, n_ab, n_ac)
    real(wp), intent(in) :: lo, hi, length, m1, m2   !< interval, slave length, master ends
    real(wp), intent(out) :: n_ab(2, 2), n_ac(2, 2)   !< exact integrals
    real(wp) :: i0, i1, i2, cs(2, 2), cm(2, 2)
    integer :: a, b
    i0 = hi - lo
    i1 = (hi**2 - lo**2)/2.0_wp
    i2 = (hi**3 - lo**3)/3.0_wp
    ! each function = c(1) + c(2) s
    cs(:, 1) = [1.0_wp, -1.0_wp/length]
    cs(:, 2) = [0.0_wp, 1.0_wp/length]
    cm(:, 1) = [m2/(m2 - m1), -1.0_wp/(m2 - m1)]
    cm(:, 2) = [-m1/(m2 - m1), 1.0_wp/(m2 - m1)]
    do a = 1, 2
      do b = 1, 2
        n_ab(a, b) = cs(1, a)*cs(1, b)*i0 + (cs(1, a)*cs(2, b) + cs(2, a)*cs(1, b))*i1 &
            + cs(2, a)*cs(2, b)*i2
        n_ac(a, b) = cs(1, a)*cm(1, b)*i0 + (cs(1, a)*cm(2, b) + cs(2, a)*cm(1, b))*i1 &
            + cs(2, a)*cm(2, b)*i2
      end do
    end do
  end subroutine exact_interval

  !> No overlap, touching, degenerate slave, master along the normal, rigid motion, reversed
  !> master numbering, tolerance.
  subroutine test_degenerate_and_invariance_2d()
    real(wp) :: xs(2, 2), xm(2, 2), n_ab(2, 2), n_ac(2, 2), overlap, ab2(2, 2), ac2(2, 2)
    real(wp) :: overlap2, r(2, 2), shift(2), angle
    xs = reshape([0.0_wp, 0.0_wp, 1.0_wp, 0.0_wp], [2, 2])
    xm = reshape([1.5_wp, -0.1_wp, 3.0_wp, -0.1_wp], [2, 2])
    call mortar_segment_pair_2d(xs, xm, n_ab, n_ac, overlap)
    call check(all(n_ab == 0.0_wp) .and. all(n_ac == 0.0_wp) .and. overlap == 0.0_wp, &
        'no overlap 2D: zeros')
    xm = reshape([1.0_wp, -0.1_wp, 3.0_wp, -0.1_wp], [2, 2])
    call mortar_segment_pair_2d(xs, xm, n_ab, n_ac, overlap)
    call check(all(n_ab == 0.0_wp) .and. overlap == 0.0_wp, 'touching end points 2D: zeros')
    xm = reshape([0.5_wp, -1.0_wp, 0.5_wp, 1.0_wp], [2, 2])
    call mortar_segment_pair_2d(xs, xm, n_ab, n_ac, overlap)
    call check(all(n_ab == 0.0_wp) .and. all(n_ac == 0.0_wp) .and. overlap == 0.0_wp, &
        'degenerate 2D: master along the slave normal gives zeros')
    call mortar_segment_pair_2d(spread([0.3_wp, 0.3_wp], 2, 2), xm, n_ab, n_ac, overlap)
    call check(all(n_ab == 0.0_wp) .and. all(n_ac == 0.0_wp) .and. overlap == 0.0_wp, &
        'degenerate 2D: zero-length slave gives zeros')
    call mortar_segment_pair_2d(spread([0.0_wp, 0.0_wp], 2, 2), xm, n_ab, n_ac, overlap)
    call check(all(n_ab == 0.0_wp) .and. overlap == 0.0_wp, &
        'degenerate 2D: zero-length slave at the origin gives zeros')
    xm = reshape([1.0_wp - 0.5_wp*OVERLAP_REL_TOL, -0.1_wp, 3.0_wp, -0.1_wp], [2, 2])
    call mortar_segment_pair_2d(xs, xm, n_ab, n_ac, overlap)
    call check(overlap == 0.0_wp .and. all(n_ab == 0.0_wp), &
        'tolerance 2D: overlap of 0.5 x OVERLAP_REL_TOL x L is dropped')
    ! rigid motion of a partly overlapping pair with a tilted master
    xs = reshape([0.1_wp, 0.2_wp, 1.3_wp, 0.5_wp], [2, 2])
    xm = reshape([1.6_wp, 0.1_wp, 0.7_wp, 0.4_wp], [2, 2])
    call mortar_segment_pair_2d(xs, xm, n_ab, n_ac, overlap)
    call check(overlap > 0.3_wp, 'invariance 2D: the test pair overlaps')
    angle = 2.3_wp
    r = reshape([cos(angle), sin(angle), -sin(angle), cos(angle)], [2, 2])
    shift = [-20.0_wp, 7.5_wp]
    call mortar_segment_pair_2d(matmul(r, xs) + spread(shift, 2, 2), &
        matmul(r, xm) + spread(shift, 2, 2), ab2, ac2, overlap2)
    ! measured 1.7e-15 (translation ~20)
    call check_small(abs(overlap2 - overlap) + max_diff(ab2, n_ab) + max_diff(ac2, n_ac), &
        1.0e-12_wp, 'invariance 2D: rigid motion leaves the weights unchanged')
    call mortar_segment_pair_2d(xs, xm(:, [2, 1]), ab2, ac2, overlap2)
    ! measured 0
    call check_small(abs(overlap2 - overlap) + max_diff(ab2, n_ab) + &
        max_diff(ac2(:, [2, 1]), n_ac), 1.0e-15_wp, &
        'orientation 2D: reversed master gives the same weights')
  end subroutine test_degenerate_and_invariance_2d

  !> 2D patch test: a segment cut 3 ways (slave) and 4 ways (master, each numbered backwards),
  !> in a rotated frame; coplanar and with the master at a gap.
  subroutine test_patch_2d()
    real(wp), parameter :: CUT_S(4) = [0.0_wp, 0.23_wp, 0.61_wp, 1.0_wp]
    real(wp), parameter :: CUT_M(5) = [0.0_wp, 0.4_wp, 0.55_wp, 0.9_wp, 1.0_wp]
    real(wp), parameter :: FIELD_GRADIENT(2) = [1.7_wp, -0.6_wp], FIELD_0 = -0.4_wp
    real(wp) :: xs_all(2, 4), xm_all(2, 5), global_ab(4, 4), global_ac(4, 5), n_ab(2, 2)
    real(wp) :: n_ac(2, 2), overlap, weighted(2), normal(2), angle, gap, err_moment, err_gap
    real(wp) :: err_field, field_s(4), field_m(5)
    integer :: s, m, a, lift
    angle = 0.8_wp
    normal = [sin(angle), -cos(angle)]
    xs_all = place_2d(CUT_S, [0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp], angle, [3.0_wp, -1.0_wp])
    do lift = 1, 2
      gap = merge(0.0_wp, -0.05_wp, lift == 1)
      xm_all = place_2d(CUT_M, [(gap, a = 1, 5)], angle, [3.0_wp, -1.0_wp])
      global_ab = 0.0_wp
      global_ac = 0.0_wp
      do s = 1, 3
        do m = 1, 4
          call mortar_segment_pair_2d(xs_all(:, s:s + 1), xm_all(:, [m + 1, m]), n_ab, n_ac, &
              overlap)
          global_ab(s:s + 1, s:s + 1) = global_ab(s:s + 1, s:s + 1) + n_ab
          global_ac(s:s + 1, [m + 1, m]) = global_ac(s:s + 1, [m + 1, m]) + n_ac
        end do
      end do
      field_s = FIELD_0 + matmul(FIELD_GRADIENT, xs_all)
      field_m = FIELD_0 + matmul(FIELD_GRADIENT, xm_all - spread(gap*normal, 2, 5))
      err_moment = 0.0_wp
      err_gap = 0.0_wp
      err_field = 0.0_wp
      do a = 1, 4
        weighted = matmul(xm_all, global_ac(a, :)) - matmul(xs_all, global_ab(a, :))
        err_gap = max(err_gap, abs(dot_product(normal, weighted)/sum(global_ab(a, :)) - gap))
        weighted = weighted - gap*sum(global_ab(a, :))*normal
        err_moment = max(err_moment, maxval(abs(weighted)))
        err_field = max(err_field, abs(dot_product(global_ac(a, :), field_m) &
            - dot_product(global_ab(a, :), field_s)))
      end do
      ! measured: moments <= 4.4e-16, field <= 4.4e-16, gap <= 1.0e-15
      call check_close(sum(global_ab), 1.0_wp, 1.0e-13_wp, 'patch 2D: sum n_AB = length')
      call check_close(sum(global_ac), 1.0_wp, 1.0e-13_wp, 'patch 2D: sum n_AC = length')
      call check_small(err_moment, 1.0e-12_wp, &
          'patch 2D: sum_C n_AC x_C = sum_B n_AB x_B (+ gap A_A n) for every slave node')
      call check_small(err_field, 1.0e-12_wp, 'patch 2D: linear field transmitted')
      call check_small(err_gap, 1.0e-12_wp, 'patch 2D: weighted gap g_A = gap')
    end do
  end subroutine test_patch_2d

  ! ---------------------------------------------------------------------------------------
  ! timing
  ! ---------------------------------------------------------------------------------------

  !> ns per pair for tri-tri, tri-quad (partial overlaps of varying shape) and segment pairs.
  subroutine benchmark()
    integer, parameter :: N_CONFIG = 64, N_REPEAT_3D = 1000, N_REPEAT_2D = 20000
    real(wp) :: xs(3, 3), xm(3, 4, N_CONFIG), n_ab(3, 3), n_ac(3, 4), overlap, total
    real(wp) :: ys(2, 2), ym(2, 2, N_CONFIG), m_ab(2, 2), m_ac(2, 2), phase
    integer(i8) :: t0, t1, rate
    integer :: k, rep, nm, n_overlapping
    character(len=160) :: line
    xs = reshape([0.0_wp, 0.0_wp, 0.0_wp, 1.0_wp, 0.1_wp, 0.0_wp, 0.2_wp, 0.9_wp, 0.0_wp], &
        [3, 3])
    ys = reshape([0.0_wp, 0.0_wp, 1.0_wp, 0.1_wp], [2, 2])
    do k = 1, N_CONFIG
      phase = 2.0_wp*PI*real(k, wp)/real(N_CONFIG, wp)
      xm(:, 1, k) = [0.5_wp*cos(phase), 0.5_wp*sin(phase), 0.1_wp]
      xm(:, 2, k) = xm(:, 1, k) + [0.9_wp, 0.2_wp*sin(3.0_wp*phase), 0.0_wp]
      xm(:, 3, k) = xm(:, 2, k) + [-0.1_wp, 0.8_wp, 0.05_wp]
      xm(:, 4, k) = xm(:, 1, k) + [0.05_wp, 0.85_wp, 0.05_wp]
      ym(:, 1, k) = [0.6_wp*cos(phase), -0.1_wp]
      ym(:, 2, k) = ym(:, 1, k) + [0.7_wp, 0.05_wp]
    end do
    do nm = 3, 4
      total = 0.0_wp
      n_overlapping = 0
      call system_clock(t0, rate)
      do rep = 1, N_REPEAT_3D
        do k = 1, N_CONFIG
          call mortar_triangle_pair_3d(xs, xm(:, :, k), nm, n_ab, n_ac, overlap)
          total = total + overlap + n_ac(1, 2)
          if (rep == 1 .and. overlap > 0.0_wp) n_overlapping = n_overlapping + 1
        end do
      end do
      call system_clock(t1)
      call check(total > 0.0_wp .and. n_overlapping > N_CONFIG/2, &
          'benchmark: most timed 3D pairs overlap')
      write(line, '(a,a,a,f8.1,a,i0,a,i0,a)') 'BENCH mortar_segmentation: ', &
          trim(merge('tri-tri ', 'tri-quad', nm == 3)), ' pair ', &
          1.0e9_wp*real(t1 - t0, wp)/real(rate, wp)/real(N_REPEAT_3D*N_CONFIG, wp), &
          ' ns (', n_overlapping, ' of ', N_CONFIG, ' configurations overlap; this build)'
      write(*, '(a)') trim(line)
    end do
    total = 0.0_wp
    call system_clock(t0, rate)
    do rep = 1, N_REPEAT_2D
      do k = 1, N_CONFIG
        call mortar_segment_pair_2d(ys, ym(:, :, k), m_ab, m_ac, overlap)
        total = total + overlap + m_ac(1, 2)
      end do
    end do
    call system_clock(t1)
    call check(total > 0.0_wp, 'benchmark: timed 2D pairs overlap')
    write(line, '(a,f8.1,a)') 'BENCH mortar_segmentation: segment pair ', &
        1.0e9_wp*real(t1 - t0, wp)/real(rate, wp)/real(N_REPEAT_2D*N_CONFIG, wp), &
        ' ns (this build)'
    write(*, '(a)') trim(line)
  end subroutine benchmark

end program test_mortar_segmentation
