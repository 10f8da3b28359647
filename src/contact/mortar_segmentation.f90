!> Geometric kernels of mortar segment-to-segment contact: the mortar integrals of one slave
!> facet against one master facet (doc/theory.md, "Mortar segmentation"; formulation 5.3).
!>
!> For a slave facet (2-node segment in 2D, 3-node triangle in 3D, linear shape functions N_A)
!> and a master facet (segment, triangle or quadrilateral, functions N_C^m) the kernels return
!>     n_AB = int N_A N_B,   n_AC = int N_A N_C^m,   overlap = int 1
!> over the part of the slave facet that the master facet covers when it is projected onto the
!> slave facet's line/plane along the slave facet's unit normal. N_C^m is the master function
!> at the master point on the slave-normal line through the integration point (3D: integrated
!> exactly as n_AC = M P, see integrate_master_triangle). The projection uses
!> the FIXED normal of the slave facet (one direction per pair); the interpolated nodal-normal
!> projection of Yang et al. (2005) is deliberately not offered, so a flat master facet maps
!> affinely and every integrand is a quadratic polynomial, integrated exactly.
!>
!> Conventions:
!> - 2D: t = (xs(:,2) - xs(:,1))/L, slave normal (t_y, -t_x), outward from the slave body, which
!>   lies on the left of N1->N2 (as *LOAD_SEGMENT in 2D, src/solver/boundary_conditions.f90).
!> - 3D: the slave triangle runs counter-clockwise seen from outside its body; the outward
!>   normal is (x2 - x1) x (x3 - x1)/|..|.
!> - The master facet may be numbered either way (rigid tool shells come in both orientations).
!> - Nothing is filtered by gap sign, distance or the direction the master faces: the weights
!>   depend only on the projections. Choosing candidate pairs is the driver's job.
!> - A master quadrilateral is replaced by 4 "pallets" (Puso & Laursen 2004): the flat
!>   triangles (c, x_i, x_i+1) about the vertex centroid c, on which N^m is linear with
!>   N_C^m(c) = 1/4. This reproduces linear fields on a planar quad, does not depend on where
!>   the numbering starts or on its direction, and treats a warped quad as 4 flat triangles.
!>   A quad with node 4 = node 3 (LS-DYNA's degenerate quad) gives the triangle's weights,
!>   with columns 3 and 4 summing to the triangle's column 3.
!> Tolerances: a pair whose overlap is below OVERLAP_REL_TOL times the slave length/area
!> returns all zeros; a degenerate slave (zero length, or a triangle with |2A| <=
!> DEGENERATE_REL_TOL h_max^2) returns all zeros. No routine allocates; all are pure.
module mefem_mortar_segmentation
  use mefem_kinds, only: wp
  implicit none
  private

  public :: mortar_segment_pair_2d, mortar_triangle_pair_3d
  public :: sutherland_hodgman, polygon_signed_area

  !> Largest polygon sutherland_hodgman returns (a convex subject of n_s vertices clipped by a
  !> convex polygon of n_c vertices has at most n_s + n_c vertices; tri-tri needs 6).
  integer, parameter, public :: MAX_POLYGON_VERTICES = 16
  !> Pairs whose overlap is below this fraction of the slave facet's length (2D) or area (3D)
  !> count as not overlapping (all weights zero). Round-off slivers of facets that only touch
  !> along an edge are ~1e-16 of the slave area; dropping a genuine overlap of this size
  !> changes A_A by at most 1e-10 relative.
  real(wp), parameter, public :: OVERLAP_REL_TOL = 1.0e-10_wp
  !> A slave triangle with twice its area <= this times its longest edge squared (a slave
  !> segment shorter than this times its largest coordinate) is degenerate: zero weights.
  real(wp), parameter, public :: DEGENERATE_REL_TOL = 1.0e-12_wp

  !> 2-point Gauss-Legendre abscissa on [-1, 1] (weights 1): exact for cubics.
  real(wp), parameter :: GAUSS2_ABSCISSA = 0.57735026918962576451_wp
  !> 3-point interior rule on a triangle, exact for quadratics: the point g has barycentric
  !> TRI3_MAJOR at vertex g and TRI3_MINOR at the other two; each weight is area/3.
  real(wp), parameter :: TRI3_MAJOR = 2.0_wp/3.0_wp, TRI3_MINOR = 1.0_wp/6.0_wp
  !> Master function value of each quad node at the vertex centroid of its pallets.
  real(wp), parameter :: PALLET_CENTRE_VALUE = 0.25_wp

contains

  !> Mortar integrals of one 2D slave segment against one master segment. The master end
  !> points are projected onto the slave segment's line along the slave normal (t_y, -t_x);
  !> the overlap is the intersection of the parameter intervals; 2-point Gauss integrates the
  !> quadratic integrands exactly. Degenerate slave, master parallel to the slave normal, or
  !> overlap < OVERLAP_REL_TOL L: all outputs zero.
  pure subroutine mortar_segment_pair_2d(xs, xm, n_ab, n_ac, overlap)
    real(wp), intent(in) :: xs(2, 2)     !< slave end points N1, N2 (columns), body on the left
    real(wp), intent(in) :: xm(2, 2)     !< master end points (either order)
    real(wp), intent(out) :: n_ab(2, 2)  !< int N_A N_B over the overlap (slave A, slave B)
    real(wp), intent(out) :: n_ac(2, 2)  !< int N_A N_C^m over the overlap (slave A, master C)
    real(wp), intent(out) :: overlap     !< overlap length (0: none)
    real(wp) :: tangent(2), length, s_master(2), master_span, s_lo, s_hi, mid, half, s
    real(wp) :: n_slave(2), n_master(2)
    integer :: g, a, b

    n_ab = 0.0_wp
    n_ac = 0.0_wp
    overlap = 0.0_wp
    tangent = xs(:, 2) - xs(:, 1)
    length = norm2(tangent)
    if (length <= DEGENERATE_REL_TOL*maxval(abs(xs))) return
    tangent = tangent/length
    ! Projecting along the normal onto the slave line keeps the tangential coordinate.
    s_master(1) = dot_product(xm(:, 1) - xs(:, 1), tangent)
    s_master(2) = dot_product(xm(:, 2) - xs(:, 1), tangent)
    master_span = s_master(2) - s_master(1)
    if (abs(master_span) <= OVERLAP_REL_TOL*length) return
    s_lo = max(0.0_wp, minval(s_master))
    s_hi = min(length, maxval(s_master))
    if (s_hi - s_lo < OVERLAP_REL_TOL*length) return
    overlap = s_hi - s_lo
    mid = 0.5_wp*(s_lo + s_hi)
    half = 0.5_wp*overlap
    do g = 1, 2
      s = mid + real(2*g - 3, wp)*GAUSS2_ABSCISSA*half
      n_slave = [1.0_wp - s/length, s/length]
      n_master(2) = (s - s_master(1))/master_span
      n_master(1) = 1.0_wp - n_master(2)
      do b = 1, 2
        do a = 1, 2
          n_ab(a, b) = n_ab(a, b) + half*n_slave(a)*n_slave(b)
          n_ac(a, b) = n_ac(a, b) + half*n_slave(a)*n_master(b)
        end do
      end do
    end do
  end subroutine mortar_segment_pair_2d

  !> Mortar integrals of one slave triangle against one master triangle or quadrilateral.
  !> The master (each pallet of a quad) is projected onto the slave plane along the slave
  !> normal, clipped against the slave triangle (Sutherland-Hodgman), the overlap polygon is
  !> fan-triangulated about its vertex average and each sub-triangle integrated with the
  !> 3-point rule exact for quadratics (n_AB; n_AC follows exactly from it and the master
  !> functions at the slave vertices, see integrate_master_triangle). Degenerate slave,
  !> invalid nm or overlap below OVERLAP_REL_TOL times the slave area: all outputs zero.
  pure subroutine mortar_triangle_pair_3d(xs, xm, nm, n_ab, n_ac, overlap)
    real(wp), intent(in) :: xs(3, 3)     !< slave vertices (columns), counter-clockwise from outside
    real(wp), intent(in) :: xm(3, 4)     !< master vertices (either orientation); column 4
                                         !< unused when nm = 3
    integer, intent(in) :: nm            !< master vertex count: 3 triangle, 4 quadrilateral
    real(wp), intent(out) :: n_ab(3, 3)  !< int N_A N_B over the overlap (slave A, slave B)
    real(wp), intent(out) :: n_ac(3, 4)  !< int N_A N_C^m (slave A, master C); column 4 zero
                                         !< when nm = 3
    real(wp), intent(out) :: overlap     !< overlap area (0: none)
    real(wp) :: edge12(3), edge13(3), perpendicular(3), e1(3), e2(3), offset(3)
    real(wp) :: slave_2d(2, 3), master_2d(2, 4), pallet_2d(2, 3), node_map(3, 4)
    real(wp) :: longest_squared, length12, along, height, slave_det
    integer :: i, j

    n_ab = 0.0_wp
    n_ac = 0.0_wp
    overlap = 0.0_wp
    if (nm /= 3 .and. nm /= 4) return
    edge12 = xs(:, 2) - xs(:, 1)
    edge13 = xs(:, 3) - xs(:, 1)
    longest_squared = max(sum(edge12**2), sum(edge13**2), sum((xs(:, 3) - xs(:, 2))**2))
    length12 = norm2(edge12)
    if (length12 <= 0.0_wp) return
    ! In-plane frame: origin x1, e1 along edge 1-2, e2 the part of edge 1-3 normal to e1
    ! (Gram-Schmidt), so e1 x e2 is the outward normal and the slave is counter-clockwise.
    e1 = edge12/length12
    along = dot_product(edge13, e1)
    perpendicular = edge13 - along*e1
    height = norm2(perpendicular)
    slave_det = length12*height
    if (slave_det <= DEGENERATE_REL_TOL*longest_squared) return
    e2 = perpendicular/height
    slave_2d(:, 1) = 0.0_wp
    slave_2d(:, 2) = [length12, 0.0_wp]
    slave_2d(:, 3) = [along, height]
    ! Projection along the normal = dropping the normal component.
    do j = 1, nm
      offset = xm(:, j) - xs(:, 1)
      master_2d(:, j) = [dot_product(offset, e1), dot_product(offset, e2)]
    end do
    if (nm == 3) then
      node_map = 0.0_wp
      do i = 1, 3
        node_map(i, i) = 1.0_wp
      end do
      call integrate_master_triangle(slave_2d, slave_det, master_2d(:, 1:3), node_map, &
          n_ab, n_ac, overlap)
    else
      ! The projection is affine, so the projected vertex centroid is the pallet centre.
      pallet_2d(:, 1) = sum(master_2d, dim=2)/real(nm, wp)
      do i = 1, 4
        j = mod(i, 4) + 1
        pallet_2d(:, 2) = master_2d(:, i)
        pallet_2d(:, 3) = master_2d(:, j)
        node_map = 0.0_wp
        node_map(1, :) = PALLET_CENTRE_VALUE
        node_map(2, i) = 1.0_wp
        node_map(3, j) = 1.0_wp
        call integrate_master_triangle(slave_2d, slave_det, pallet_2d, node_map, &
            n_ab, n_ac, overlap)
      end do
    end if
    if (overlap < OVERLAP_REL_TOL*0.5_wp*slave_det) then
      n_ab = 0.0_wp
      n_ac = 0.0_wp
      overlap = 0.0_wp
    end if
  end subroutine mortar_triangle_pair_3d

  !> Add the mortar integrals over (projected master triangle) /\ (slave triangle), both in
  !> the slave plane's 2D frame. The overlap polygon is fan-triangulated about its vertex
  !> average; the 3-point rule exact for quadratics gives M_AB = int lambda_A lambda_B
  !> (lambda: slave barycentrics). The master functions are affine on the plane, so
  !> N_C^m = sum_B P_BC lambda_B with P_BC = N_C^m at slave vertex B (extrapolated), and
  !> n_AC = M P exactly; the absolute round-off stays ~eps times the slave area even for
  !> slender masters (|P| ~ L_slave/w_master while |M| <= overlap <= l_master w_master).
  !> N_C^m at a point is sum_k mu_k node_map(k, C), mu the master triangle's barycentrics.
  pure subroutine integrate_master_triangle(slave_2d, slave_det, master_2d, node_map, &
      n_ab, n_ac, overlap)
    real(wp), intent(in) :: slave_2d(2, 3)      !< slave triangle, counter-clockwise
    real(wp), intent(in) :: slave_det           !< twice the slave area (> 0)
    real(wp), intent(in) :: master_2d(2, 3)     !< projected master triangle, either orientation
    real(wp), intent(in) :: node_map(3, 4)      !< master node values at its 3 vertices
    real(wp), intent(inout) :: n_ab(3, 3)       !< accumulated int N_A N_B
    real(wp), intent(inout) :: n_ac(3, 4)       !< accumulated int N_A N_C^m
    real(wp), intent(inout) :: overlap          !< accumulated overlap area
    real(wp) :: polygon(2, MAX_POLYGON_VERTICES), lambda(3, MAX_POLYGON_VERTICES)
    real(wp) :: centre(2), lambda_centre(3), base(3), points(3, 3), mass(3, 3), p(3, 4), mu(3)
    real(wp) :: master_det, orientation, sub_area, weight, area
    integer :: n_polygon, k, k_next, g, a, b

    master_det = cross2(master_2d(:, 2) - master_2d(:, 1), master_2d(:, 3) - master_2d(:, 1))
    ! A master seen edge-on covers nothing (and its barycentrics would be undefined).
    if (abs(master_det) <= OVERLAP_REL_TOL*slave_det) return
    if (bounding_boxes_apart(master_2d, slave_2d)) return
    call sutherland_hodgman(3, master_2d, 3, slave_2d, n_polygon, polygon)
    if (n_polygon < 3) return
    ! The clipped polygon keeps the master's orientation.
    orientation = sign(1.0_wp, master_det)
    ! The barycentrics are affine: evaluate at the vertices, average for the centre.
    centre = 0.0_wp
    lambda_centre = 0.0_wp
    do k = 1, n_polygon
      call barycentric(slave_2d, slave_det, polygon(:, k), lambda(:, k))
      centre = centre + polygon(:, k)
      lambda_centre = lambda_centre + lambda(:, k)
    end do
    centre = centre/real(n_polygon, wp)
    lambda_centre = lambda_centre/real(n_polygon, wp)
    mass = 0.0_wp
    area = 0.0_wp
    do k = 1, n_polygon
      k_next = k + 1
      if (k == n_polygon) k_next = 1
      sub_area = 0.5_wp*orientation*cross2(polygon(:, k) - centre, polygon(:, k_next) - centre)
      area = area + sub_area
      weight = sub_area/3.0_wp
      ! Gauss point g: TRI3_MAJOR at vertex g of (centre, v_k, v_k+1), TRI3_MINOR elsewhere.
      base = TRI3_MINOR*(lambda_centre + lambda(:, k) + lambda(:, k_next))
      points(:, 1) = base + (TRI3_MAJOR - TRI3_MINOR)*lambda_centre
      points(:, 2) = base + (TRI3_MAJOR - TRI3_MINOR)*lambda(:, k)
      points(:, 3) = base + (TRI3_MAJOR - TRI3_MINOR)*lambda(:, k_next)
      do g = 1, 3
        do b = 1, 3
          do a = 1, b
            mass(a, b) = mass(a, b) + weight*points(a, g)*points(b, g)
          end do
        end do
      end do
    end do
    do b = 1, 3
      do a = b + 1, 3
        mass(a, b) = mass(b, a)
      end do
    end do
    ! P(B, C): master functions at the slave vertices.
    do b = 1, 3
      call barycentric(master_2d, master_det, slave_2d(:, b), mu)
      p(b, :) = mu(1)*node_map(1, :) + mu(2)*node_map(2, :) + mu(3)*node_map(3, :)
    end do
    n_ab = n_ab + mass
    do b = 1, 4
      n_ac(:, b) = n_ac(:, b) + mass(:, 1)*p(1, b) + mass(:, 2)*p(2, b) + mass(:, 3)*p(3, b)
    end do
    overlap = overlap + area
  end subroutine integrate_master_triangle

  !> Clip a convex polygon (subject, either orientation) by a convex counter-clockwise polygon
  !> (clip) with the Sutherland-Hodgman algorithm: one pass per clip edge keeps the part on
  !> its left (points on the edge line count as inside). The result follows the subject's
  !> orientation and may contain repeated points when edges coincide (zero-area, harmless).
  !> n_result = 0: no intersection; -1: n_subject + n_clip > MAX_POLYGON_VERTICES (refused).
  !> Columns of result beyond n_result are undefined.
  pure subroutine sutherland_hodgman(n_subject, subject, n_clip, clip, n_result, result)
    integer, intent(in) :: n_subject                  !< subject vertex count
    real(wp), intent(in) :: subject(2, n_subject)     !< subject polygon (columns)
    integer, intent(in) :: n_clip                     !< clip vertex count
    real(wp), intent(in) :: clip(2, n_clip)           !< clip polygon, counter-clockwise
    integer, intent(out) :: n_result                  !< result vertex count
    real(wp), intent(out) :: result(2, MAX_POLYGON_VERTICES)  !< clipped polygon (columns
                                                              !< 1:n_result)
    real(wp) :: previous(2, MAX_POLYGON_VERTICES), side(MAX_POLYGON_VERTICES)
    real(wp) :: edge(2), start(2)
    integer :: e, k, k_next, n_previous
    logical :: inside_k, inside_next

    if (n_subject + n_clip > MAX_POLYGON_VERTICES) then
      n_result = -1
      return
    end if
    n_result = n_subject
    result(:, 1:n_subject) = subject
    do e = 1, n_clip
      if (n_result == 0) exit
      start = clip(:, e)
      if (e < n_clip) then
        edge = clip(:, e + 1) - start
      else
        edge = clip(:, 1) - start
      end if
      n_previous = n_result
      previous(:, 1:n_previous) = result(:, 1:n_previous)
      do k = 1, n_previous
        side(k) = cross2(edge, previous(:, k) - start)
      end do
      n_result = 0
      do k = 1, n_previous
        k_next = k + 1
        if (k == n_previous) k_next = 1
        inside_k = side(k) >= 0.0_wp
        inside_next = side(k_next) >= 0.0_wp
        if (inside_k .and. n_result < MAX_POLYGON_VERTICES) then
          n_result = n_result + 1
          result(:, n_result) = previous(:, k)
        end if
        if ((inside_k .neqv. inside_next) .and. n_result < MAX_POLYGON_VERTICES) then
          n_result = n_result + 1
          result(:, n_result) = previous(:, k) + side(k)/(side(k) - side(k_next)) &
              *(previous(:, k_next) - previous(:, k))
        end if
      end do
    end do
  end subroutine sutherland_hodgman

  !> True when the bounding boxes of two triangles do not overlap (touching counts as apart).
  pure logical function bounding_boxes_apart(t1, t2)
    real(wp), intent(in) :: t1(2, 3), t2(2, 3)   !< triangles (columns)
    integer :: i
    bounding_boxes_apart = .false.
    do i = 1, 2
      if (max(t1(i, 1), t1(i, 2), t1(i, 3)) <= min(t2(i, 1), t2(i, 2), t2(i, 3)) .or. &
          min(t1(i, 1), t1(i, 2), t1(i, 3)) >= max(t2(i, 1), t2(i, 2), t2(i, 3))) then
        bounding_boxes_apart = .true.
      end if
    end do
  end function bounding_boxes_apart

  !> Signed area of a polygon (shoelace): positive when counter-clockwise.
  pure function polygon_signed_area(n, polygon) result(area)
    integer, intent(in) :: n                     !< vertex count
    real(wp), intent(in) :: polygon(2, n)        !< vertices (columns)
    real(wp) :: area
    integer :: k
    area = 0.0_wp
    do k = 1, n
      area = area + cross2(polygon(:, k), polygon(:, mod(k, n) + 1))
    end do
    area = 0.5_wp*area
  end function polygon_signed_area

  !> Barycentric coordinates of the 2D point q in a triangle with signed double area det.
  pure subroutine barycentric(triangle, det, q, lambda)
    real(wp), intent(in) :: triangle(2, 3)   !< vertices (columns)
    real(wp), intent(in) :: det              !< cross2(t2 - t1, t3 - t1), nonzero
    real(wp), intent(in) :: q(2)             !< point
    real(wp), intent(out) :: lambda(3)       !< barycentrics, summing to 1
    lambda(1) = ((triangle(1, 2) - q(1))*(triangle(2, 3) - q(2)) &
        - (triangle(2, 2) - q(2))*(triangle(1, 3) - q(1)))/det
    lambda(2) = ((triangle(1, 3) - q(1))*(triangle(2, 1) - q(2)) &
        - (triangle(2, 3) - q(2))*(triangle(1, 1) - q(1)))/det
    lambda(3) = 1.0_wp - lambda(1) - lambda(2)
  end subroutine barycentric

  !> z component of the cross product of two 2D vectors.
  pure function cross2(a, b) result(z)
    real(wp), intent(in) :: a(2), b(2)   !< vectors
    real(wp) :: z
    z = a(1)*b(2) - a(2)*b(1)
  end function cross2

end module mefem_mortar_segmentation
