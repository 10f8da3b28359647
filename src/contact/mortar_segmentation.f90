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
!> - 3D clipping runs in the slave triangle's barycentric coordinates lambda: the slave edges
!>   are the lines lambda_i = 0, so clipping by the slave is keeping lambda_i >= 0 (no
!>   division per polygon vertex), a master whose vertices all have lambda_i <= 0 for one i
!>   lies beyond that edge (rejected at once), and the integrands are polynomials in lambda.
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
  !> Master function value of each quad node at the vertex centroid of its pallets.
  real(wp), parameter :: PALLET_CENTRE_VALUE = 0.25_wp
  !> Master nodes at the vertices of a master triangle (no pallet centre).
  integer, parameter :: TRIANGLE_CORNERS(3) = [1, 2, 3]
  !> Exact integral of a product of barycentrics over a triangle T:
  !> int_T lambda_i lambda_j = |T| (1 + delta_ij) / LINEAR_PRODUCT_DIVISOR.
  real(wp), parameter :: LINEAR_PRODUCT_DIVISOR = 12.0_wp

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
  !> normal, clipped against the slave triangle (Sutherland-Hodgman in the slave's
  !> barycentric coordinates), the overlap polygon is fan-triangulated about its vertex
  !> average and each sub-triangle integrated exactly (n_AB; n_AC follows exactly from it
  !> and the master functions at the slave vertices, see integrate_master_triangle). A
  !> master entirely beyond one slave edge is rejected before any clipping. Degenerate slave,
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
    real(wp) :: slave_2d(2, 3), master_2d(2, 4), pallet_2d(2, 3)
    real(wp) :: master_lambda(3, 4), pallet_lambda(3, 3)
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
    ! Projection along the normal = dropping the normal component; the master vertices in
    ! the slave's barycentric coordinates.
    do j = 1, nm
      offset = xm(:, j) - xs(:, 1)
      master_2d(:, j) = [dot_product(offset, e1), dot_product(offset, e2)]
      call barycentric(slave_2d, slave_det, master_2d(:, j), master_lambda(:, j))
    end do
    ! most candidates of the search do not overlap: the whole master beyond one slave edge
    do i = 1, 3
      if (all(master_lambda(i, 1:nm) <= 0.0_wp)) return
    end do
    if (nm == 3) then
      call integrate_master_triangle(slave_2d, slave_det, master_2d(:, 1:3), &
          master_lambda(:, 1:3), TRIANGLE_CORNERS, n_ab, n_ac, overlap)
    else
      ! The projection is affine, so the projected vertex centroid is the pallet centre.
      pallet_2d(:, 1) = sum(master_2d, dim=2)/real(nm, wp)
      pallet_lambda(:, 1) = sum(master_lambda, dim=2)/real(nm, wp)
      do i = 1, 4
        j = mod(i, 4) + 1
        pallet_2d(:, 2) = master_2d(:, i)
        pallet_2d(:, 3) = master_2d(:, j)
        pallet_lambda(:, 2) = master_lambda(:, i)
        pallet_lambda(:, 3) = master_lambda(:, j)
        call integrate_master_triangle(slave_2d, slave_det, pallet_2d, pallet_lambda, &
            [0, i, j], n_ab, n_ac, overlap)
      end do
    end if
    if (overlap < OVERLAP_REL_TOL*0.5_wp*slave_det) then
      n_ab = 0.0_wp
      n_ac = 0.0_wp
      overlap = 0.0_wp
    end if
  end subroutine mortar_triangle_pair_3d

  !> Add the mortar integrals over (projected master triangle) /\ (slave triangle). The master
  !> triangle, given in the slave plane's 2D frame and in the slave's barycentric coordinates
  !> lambda, is clipped by lambda_3 >= 0, lambda_1 >= 0, lambda_2 >= 0 (the slave edges 1-2,
  !> 2-3, 3-1); the overlap polygon is fan-triangulated about its vertex average, and on each
  !> fan triangle T (vertices with lambda values u, v, w, area |T|) the integrand, a product
  !> of two linear functions, is integrated exactly: int_T lambda_A lambda_B = |T|/12
  !> (s_A s_B + u_A u_B + v_A v_B + w_A w_B), s = u + v + w; summed over the fan, each
  !> polygon vertex collects the weights of its two fan triangles and the centre the total.
  !> The master functions are affine on the plane, so N_C^m = sum_B P_BC lambda_B with
  !> P_BC = N_C^m at slave vertex B (extrapolated), and n_AC = M P exactly; the absolute
  !> round-off stays ~eps times the slave area even for slender masters (|P| ~
  !> L_slave/w_master while |M| <= overlap <= l_master w_master). Vertex k of the master
  !> triangle is master node corner(k) (N = 1 there, 0 at the other nodes), or the centre of
  !> a quad's pallets when corner(k) = 0 (N = PALLET_CENTRE_VALUE for all four nodes).
  pure subroutine integrate_master_triangle(slave_2d, slave_det, master_2d, master_lambda, &
      corner, n_ab, n_ac, overlap)
    real(wp), intent(in) :: slave_2d(2, 3)      !< slave triangle, counter-clockwise
    real(wp), intent(in) :: slave_det           !< twice the slave area (> 0)
    real(wp), intent(in) :: master_2d(2, 3)     !< projected master triangle, either orientation
    real(wp), intent(in) :: master_lambda(3, 3) !< its vertices' slave barycentrics (columns)
    integer, intent(in) :: corner(3)            !< master node at each vertex, 0: pallet centre
    real(wp), intent(inout) :: n_ab(3, 3)       !< accumulated int N_A N_B
    real(wp), intent(inout) :: n_ac(3, 4)       !< accumulated int N_A N_C^m
    real(wp), intent(inout) :: overlap          !< accumulated overlap area
    real(wp) :: lambda(3, MAX_POLYGON_VERTICES), scratch(3, MAX_POLYGON_VERTICES)
    real(wp) :: vertex_weight(MAX_POLYGON_VERTICES)
    real(wp) :: lambda_centre(3), total(3), mass(3, 3), p(3, 4), mu(3)
    real(wp) :: master_det, orientation, sub_area, weight, area
    integer :: n_polygon, n_scratch, k, k_next, a, b

    master_det = cross2(master_2d(:, 2) - master_2d(:, 1), master_2d(:, 3) - master_2d(:, 1))
    ! A master seen edge-on covers nothing (and its barycentrics would be undefined).
    if (abs(master_det) <= OVERLAP_REL_TOL*slave_det) return
    do k = 1, 3     ! this pallet lies beyond one slave edge
      if (all(master_lambda(k, :) <= 0.0_wp)) return
    end do
    n_polygon = 3
    lambda(:, 1:3) = master_lambda
    call clip_barycentric(3, n_polygon, lambda, n_scratch, scratch)
    call clip_barycentric(1, n_scratch, scratch, n_polygon, lambda)
    call clip_barycentric(2, n_polygon, lambda, n_scratch, scratch)
    n_polygon = n_scratch
    if (n_polygon < 3) return
    ! The clipped polygon keeps the master's orientation.
    orientation = sign(1.0_wp, master_det)
    lambda_centre = 0.0_wp
    do k = 1, n_polygon
      lambda_centre = lambda_centre + scratch(:, k)
    end do
    lambda_centre = lambda_centre/real(n_polygon, wp)
    mass = 0.0_wp
    area = 0.0_wp
    vertex_weight(1:n_polygon) = 0.0_wp
    do k = 1, n_polygon
      k_next = k + 1
      if (k == n_polygon) k_next = 1
      ! area from the barycentrics: (lambda_2, lambda_3) map to the plane with det slave_det
      sub_area = 0.5_wp*orientation*slave_det*cross2(scratch(2:3, k) - lambda_centre(2:3), &
                                                     scratch(2:3, k_next) - lambda_centre(2:3))
      area = area + sub_area
      weight = sub_area/LINEAR_PRODUCT_DIVISOR
      vertex_weight(k) = vertex_weight(k) + weight
      vertex_weight(k_next) = vertex_weight(k_next) + weight
      total = lambda_centre + scratch(:, k) + scratch(:, k_next)
      do b = 1, 3
        do a = 1, b
          mass(a, b) = mass(a, b) + weight*total(a)*total(b)
        end do
      end do
    end do
    do k = 1, n_polygon
      do b = 1, 3
        do a = 1, b
          mass(a, b) = mass(a, b) + vertex_weight(k)*scratch(a, k)*scratch(b, k)
        end do
      end do
    end do
    do b = 1, 3
      do a = 1, b
        mass(a, b) = mass(a, b) + area/LINEAR_PRODUCT_DIVISOR*lambda_centre(a)*lambda_centre(b)
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
      p(b, :) = 0.0_wp
      do k = 1, 3
        if (corner(k) == 0) then
          p(b, :) = p(b, :) + mu(k)*PALLET_CENTRE_VALUE
        else
          p(b, corner(k)) = p(b, corner(k)) + mu(k)
        end if
      end do
    end do
    n_ab = n_ab + mass
    do b = 1, 4
      n_ac(:, b) = n_ac(:, b) + mass(:, 1)*p(1, b) + mass(:, 2)*p(2, b) + mass(:, 3)*p(3, b)
    end do
    overlap = overlap + area
  end subroutine integrate_master_triangle

  !> One Sutherland-Hodgman pass in barycentric coordinates: keep the part of a convex
  !> polygon where lambda_i >= 0 (points on the line count as inside). New vertices are
  !> interpolated along the cut edges and get lambda_i = 0 exactly.
  pure subroutine clip_barycentric(i, n_in, polygon_in, n_out, polygon_out)
    integer, intent(in) :: i                                   !< barycentric kept >= 0
    integer, intent(in) :: n_in                                !< input vertex count
    real(wp), intent(in) :: polygon_in(3, MAX_POLYGON_VERTICES)    !< input (columns 1:n_in)
    integer, intent(out) :: n_out                              !< output vertex count
    real(wp), intent(out) :: polygon_out(3, MAX_POLYGON_VERTICES)  !< output (1:n_out)
    real(wp) :: side, side_next
    integer :: k, k_next
    n_out = 0
    do k = 1, n_in
      k_next = k + 1
      if (k == n_in) k_next = 1
      side = polygon_in(i, k)
      side_next = polygon_in(i, k_next)
      if (side >= 0.0_wp .and. n_out < MAX_POLYGON_VERTICES) then
        n_out = n_out + 1
        polygon_out(:, n_out) = polygon_in(:, k)
      end if
      if (((side >= 0.0_wp) .neqv. (side_next >= 0.0_wp)) .and. &
          n_out < MAX_POLYGON_VERTICES) then
        n_out = n_out + 1
        polygon_out(:, n_out) = polygon_in(:, k) + side/(side - side_next) &
            *(polygon_in(:, k_next) - polygon_in(:, k))
        polygon_out(i, n_out) = 0.0_wp
      end if
    end do
  end subroutine clip_barycentric

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
