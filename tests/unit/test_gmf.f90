!> GMF approximation and ME-FEM enrichment constants: partition of unity, linear
!> reproduction, Kronecker delta at the boundary, gradients against finite differences,
!> the symmetric integration rule (seed eqs. 5-6), and the reference tables of
!> formulation.md sections 2.4, 2.5 and 2.8 as oracles (with the tolerance each table allows).
program test_gmf
  use mefem_kinds, only: wp
  use mefem_testing, only: test_start, test_finish, check, check_close
  use mefem_errors, only: status_t
  use mefem_strings, only: rtoa
  use mefem_gmf, only: gmf_shape, cubic_spline, GMF_ATAN, GMF_EXP
  use mefem_enrichment, only: enrichment_t, enrichment_setup, reference_simplex
  implicit none

  real(wp), parameter :: RATIOS(5) = [1.1_wp, 1.25_wp, 1.5_wp, 2.0_wp, 3.0_wp]
  ! formulation.md 2.4 (kappa), 2.5 (centroid values), 2.8 (mean of the enrichment)
  real(wp), parameter :: KAPPA_2D(5) = [0.97306_wp, 0.92860_wp, 0.84458_wp, 0.71148_wp, 0.59581_wp]
  real(wp), parameter :: KAPPA_3D(5) = [0.9605_wp, 0.9122_wp, 0.8269_wp, 0.6981_wp, 0.5902_wp]
  real(wp), parameter :: CENTROID_2D(5) = [0.608426_wp, 0.517165_wp, 0.423777_wp, 0.340946_wp, &
                                           0.288881_wp]
  real(wp), parameter :: CENTROID_3D(5) = [0.589306_wp, 0.485010_wp, 0.379796_wp, 0.290789_wp, &
                                           0.237862_wp]
  real(wp), parameter :: MEAN_2D_ATAN(5) = [0.2912_wp, 0.2628_wp, 0.2263_wp, 0.1863_wp, 0.1585_wp]
  real(wp), parameter :: MEAN_2D_EXP(5) = [0.2929_wp, 0.2673_wp, 0.2340_wp, 0.1981_wp, 0.1733_wp]
  real(wp), parameter :: MEAN_3D_ATAN(5) = [0.226_wp, 0.203_wp, 0.172_wp, 0.137_wp, 0.112_wp]
  real(wp), parameter :: MEAN_3D_EXP(5) = [0.229_wp, 0.211_wp, 0.184_wp, 0.152_wp, 0.131_wp]

  call test_start('gmf')
  call test_reproduction(2, GMF_ATAN)
  call test_reproduction(3, GMF_ATAN)
  call test_reproduction(2, GMF_EXP)
  call test_reproduction(3, GMF_EXP)
  call test_boundary()
  call test_symmetric_rule()
  call test_gradient_oracle()
  call test_tables()
  call test_bad_support()
  call test_finish()

contains

  !> Random interior points: partition of unity, linear reproduction, convexity, and the
  !> gradient against central differences.
  subroutine test_reproduction(dim, kind)
    integer, intent(in) :: dim, kind
    real(wp) :: xn(dim, dim+2), x(dim), bary(dim+1), psi(dim+2), dpsi(dim, dim+2)
    real(wp) :: pp(dim+2), pm(dim+2), dd(dim, dim+2), fd(dim, dim+2), h, worst_pu, worst_lin
    real(wp) :: worst_fd, worst_neg, scale
    integer :: sample, j
    logical :: ok, all_ok
    character(len=32) :: tag
    write(tag, '(i0,a,a)') dim, 'D ', merge('atan', 'exp ', kind == GMF_ATAN)
    call reference_simplex(dim, xn)
    worst_pu = 0.0_wp
    worst_lin = 0.0_wp
    worst_fd = 0.0_wp
    worst_neg = 0.0_wp
    all_ok = .true.
    h = 1.0e-6_wp
    do sample = 1, 40
      call random_number(bary)
      bary = 0.02_wp + bary
      bary = bary/sum(bary)
      x = matmul(xn(:, 1:dim+1), bary)
      call gmf_shape(kind, 1.5_wp, xn, x, psi, dpsi, ok)
      all_ok = all_ok .and. ok
      worst_pu = max(worst_pu, abs(sum(psi) - 1.0_wp))
      worst_lin = max(worst_lin, maxval(abs(matmul(xn, psi) - x)))
      worst_neg = min(worst_neg, minval(psi))
      do j = 1, dim
        x(j) = x(j) + h
        call gmf_shape(kind, 1.5_wp, xn, x, pp, dd, ok)
        x(j) = x(j) - 2.0_wp*h
        call gmf_shape(kind, 1.5_wp, xn, x, pm, dd, ok)
        x(j) = x(j) + h
        fd(j, :) = (pp - pm)/(2.0_wp*h)
      end do
      scale = maxval(abs(dpsi))
      worst_fd = max(worst_fd, maxval(abs(fd - dpsi))/scale)
    end do
    call check(all_ok, trim(tag)//': Newton converged at 40 interior points')
    ! round-off level: the reproduction is solved to 1e-12 a
    call check(worst_pu < 1.0e-14_wp, trim(tag)//': partition of unity')
    call check(worst_lin < 1.0e-11_wp, trim(tag)//': linear reproduction')
    call check(worst_neg >= 0.0_wp, trim(tag)//': convex (all Psi >= 0)')
    ! central differences with h = 1e-6 have truncation ~h^2 and round-off ~1e-16/h
    call check(worst_fd < 1.0e-6_wp, trim(tag)//': gradient matches central differences')
  end subroutine test_reproduction

  !> Kronecker delta on the element boundary: near a vertex that corner's Psi is 1, near an
  !> edge midpoint the off-edge nodes vanish.
  subroutine test_boundary()
    real(wp) :: xn(2, 4), psi(4), dpsi(2, 4), x(2), mid(2)
    logical :: ok
    call reference_simplex(2, xn)
    x = xn(:, 3) + 1.0e-7_wp*(xn(:, 4) - xn(:, 3))
    call gmf_shape(GMF_ATAN, 1.5_wp, xn, x, psi, dpsi, ok)
    call check(ok .and. abs(psi(3) - 1.0_wp) < 1.0e-5_wp .and. maxval(psi([1, 2, 4])) < 1.0e-5_wp, &
        'Kronecker delta at a vertex (distance 1e-7)')
    mid = 0.5_wp*(xn(:, 1) + xn(:, 2))
    x = mid + 1.0e-7_wp*(xn(:, 4) - mid)
    call gmf_shape(GMF_ATAN, 1.5_wp, xn, x, psi, dpsi, ok)
    call check(ok .and. maxval(psi(3:4)) < 1.0e-6_wp .and. abs(psi(1) - 0.5_wp) < 1.0e-6_wp, &
        'enriched and opposite node vanish on an edge; edge nodes linear')
  end subroutine test_boundary

  !> Seed eqs. 5-6: the enrichment gradients at the three (four) side points sum to zero, so
  !> the rule integrates every corner gradient exactly (sum = (dim+1) grad N_I).
  subroutine test_symmetric_rule()
    real(wp) :: xn2(2, 4), xn3(3, 5), psi2(4), d2(2, 4), psi3(5), d3(3, 5), s2(2, 4), s3(3, 5)
    real(wp) :: side(3), gradn2(2, 3)
    integer :: k, corners(2)
    logical :: ok
    call reference_simplex(2, xn2)
    s2 = 0.0_wp
    do k = 1, 3
      corners = pack([1, 2, 3], [1, 2, 3] /= k)
      side(1:2) = 0.5_wp*(xn2(:, corners(1)) + xn2(:, corners(2)))
      call gmf_shape(GMF_ATAN, 1.5_wp, xn2, side(1:2) + 1.0e-3_wp*(xn2(:, 4) - side(1:2)), &
                     psi2, d2, ok)
      s2 = s2 + d2
    end do
    call check(maxval(abs(s2(:, 4))) < 1.0e-10_wp, '2D: sum of enrichment gradients at the 3 points')
    ! grad N of the reference triangle
    gradn2(:, 1) = [-1.0_wp, -1.0_wp/sqrt(3.0_wp)]
    gradn2(:, 2) = [1.0_wp, -1.0_wp/sqrt(3.0_wp)]
    gradn2(:, 3) = [0.0_wp, 2.0_wp/sqrt(3.0_wp)]
    call check(maxval(abs(s2(:, 1:3) - 3.0_wp*gradn2)) < 1.0e-10_wp, &
        '2D: 3-point rule integrates the corner gradients exactly')
    call reference_simplex(3, xn3)
    s3 = 0.0_wp
    do k = 1, 4
      side = (sum(xn3(:, 1:4), dim=2) - xn3(:, k))/3.0_wp
      call gmf_shape(GMF_ATAN, 1.5_wp, xn3, side + 1.0e-3_wp*(xn3(:, 5) - side), psi3, d3, ok)
      s3 = s3 + d3
    end do
    ! gradients of size ~5 solved to ~1e-11 relative
    call check(maxval(abs(s3(:, 5))) < 1.0e-9_wp, '3D: sum of enrichment gradients at the 4 points', &
        detail=rtoa(maxval(abs(s3(:, 5)))))
  end subroutine test_symmetric_rule

  !> formulation.md 2.4: gradients at the midpoint of edge 1-2, a/L = 1.5, atan (6 digits).
  subroutine test_gradient_oracle()
    real(wp) :: xn(2, 4), psi(4), g1(2, 4), g2(2, 4), mid(2), g(2, 4), want(2, 4)
    logical :: ok
    call reference_simplex(2, xn)
    mid = [0.5_wp, 0.0_wp]
    call gmf_shape(GMF_ATAN, 1.5_wp, xn, mid + 1.0e-5_wp*(xn(:, 4) - mid), psi, g1, ok)
    call gmf_shape(GMF_ATAN, 1.5_wp, xn, mid + 0.25e-5_wp*(xn(:, 4) - mid), psi, g2, ok)
    g = (4.0_wp*g2 - g1)/3.0_wp
    want = reshape([-1.0_wp, -1.552586_wp, 1.0_wp, -1.552586_wp, 0.0_wp, 0.179465_wp, &
                    0.0_wp, 2.925707_wp], [2, 4])
    call check_close(reshape(g, [8]), reshape(want, [8]), 0.0_wp, &
        'gradient oracle at the edge midpoint (table to 6 decimals)', atol=1.0e-6_wp)
  end subroutine test_gradient_oracle

  !> kappa, centroid values and mean enrichment against the tables; kappa also against the
  !> asymptotic closed form phi_c/(phi_c + phi_o) for atan (doc/theory.md).
  subroutine test_tables()
    type(enrichment_t) :: en
    type(status_t) :: status
    integer :: i
    real(wp) :: phi_c, phi_o, dphi, altitude
    character(len=16) :: tag
    do i = 1, 5
      write(tag, '(a,f4.2)') 'a/L=', RATIOS(i)
      call enrichment_setup(2, GMF_ATAN, RATIOS(i), 0.0_wp, en, status)
      call check(status%ok, '2D atan setup '//tag)
      ! kappa: the table's 5 decimals (its own extrapolation is finer than that)
      call check_close(en%kappa, KAPPA_2D(i), 0.0_wp, '2D atan kappa '//tag, atol=1.0e-5_wp)
      altitude = sqrt(3.0_wp)/2.0_wp
      call cubic_spline(altitude/3.0_wp/RATIOS(i), phi_c, dphi)
      call cubic_spline(altitude/RATIOS(i), phi_o, dphi)
      call check_close(en%kappa, phi_c/(phi_c + phi_o), 1.0e-7_wp, &
          '2D atan kappa = closed form '//tag)
      call check_close(en%centroid_value, CENTROID_2D(i), 0.0_wp, '2D centroid value '//tag, &
          atol=1.0e-6_wp)
      ! the table's centroid rule on 3200 sub-triangles errs by about 3e-4 (O(h^2))
      call check_close(en%mass_fraction, MEAN_2D_ATAN(i), 0.0_wp, '2D atan mean '//tag, &
          atol=5.0e-4_wp)
      call enrichment_setup(2, GMF_EXP, RATIOS(i), 0.0_wp, en, status)
      call check_close(en%kappa, 1.0_wp, 1.0e-7_wp, '2D exp kappa = 1 '//tag)
      call check_close(en%mass_fraction, MEAN_2D_EXP(i), 0.0_wp, '2D exp mean '//tag, &
          atol=5.0e-4_wp)
      call enrichment_setup(3, GMF_ATAN, RATIOS(i), 0.0_wp, en, status)
      call check(status%ok, '3D atan setup '//tag)
      call check_close(en%kappa, KAPPA_3D(i), 0.0_wp, '3D atan kappa '//tag, atol=1.0e-4_wp)
      altitude = sqrt(2.0_wp/3.0_wp)
      call cubic_spline(altitude/4.0_wp/RATIOS(i), phi_c, dphi)
      call cubic_spline(altitude/RATIOS(i), phi_o, dphi)
      call check_close(en%kappa, phi_c/(phi_c + phi_o), 1.0e-7_wp, &
          '3D atan kappa = closed form '//tag)
      call check_close(en%centroid_value, CENTROID_3D(i), 0.0_wp, '3D centroid value '//tag, &
          atol=1.0e-6_wp)
      ! the table's Monte Carlo means are +-0.001 (a/L 1.25-2) and +-0.003 (1.1, 3.0)
      call check_close(en%mass_fraction, MEAN_3D_ATAN(i), 0.0_wp, '3D atan mean '//tag, &
          atol=merge(1.5e-3_wp, 3.0e-3_wp, i >= 2 .and. i <= 4))
      call enrichment_setup(3, GMF_EXP, RATIOS(i), 0.0_wp, en, status)
      call check_close(en%kappa, 1.0_wp, 1.0e-7_wp, '3D exp kappa = 1 '//tag)
      call check_close(en%mass_fraction, MEAN_3D_EXP(i), 0.0_wp, '3D exp mean '//tag, &
          atol=merge(1.5e-3_wp, 3.0e-3_wp, i >= 2 .and. i <= 4))
    end do
  end subroutine test_tables

  !> A support that does not cover the element is refused with a message.
  subroutine test_bad_support()
    type(enrichment_t) :: en
    type(status_t) :: status
    call enrichment_setup(2, GMF_ATAN, 0.9_wp, 0.0_wp, en, status)
    call check(.not. status%ok .and. allocated(status%message), 'a/L <= 1 is refused')
  end subroutine test_bad_support

end program test_gmf
