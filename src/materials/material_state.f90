!> History (state) of one material point, shared by every material law.
!>
!> A point's history is a flat array hist(NHIST) so that element groups can store it as
!> hist(NHIST, n_points); the entries are addressed only through the named offsets below:
!> - HIST_F .. HIST_F+8: F_n, the deformation gradient of the last converged state, column by
!>   column (F11 F21 F31 F12 F22 F32 F13 F23 F33); initially I;
!> - HIST_BE .. HIST_BE+5: be_bar_n, the isochoric elastic left Cauchy-Green tensor
!>   (symmetric, det = 1), Voigt order xx yy zz xy yz zx; initially I. The plasticity law
!>   evolves it by the return map; the hyperelastic laws store their isochoric b_bar there;
!> - HIST_ALPHA: alpha_n, the equivalent plastic strain (0 for elastic laws).
!> The laws read hist_old and write hist_new; the driver keeps hist_old until the step is
!> accepted (Newton converged), so a cut step simply discards hist_new.
module mefem_material_state
  use mefem_kinds, only: wp
  use mefem_tensor_algebra, only: IDENTITY, symmetric_to_voigt, voigt_to_symmetric
  implicit none
  private

  integer, parameter, public :: HIST_F = 1        !< first of 9 entries: F_n (column major)
  integer, parameter, public :: HIST_BE = 10      !< first of 6 entries: be_bar_n (Voigt)
  integer, parameter, public :: HIST_ALPHA = 16   !< equivalent plastic strain alpha_n
  integer, parameter, public :: NHIST = 16        !< length of a point's history
  !> Points (cells) per block of the block kernels of the explicit cell loop: the leading
  !> dimension of their structure-of-arrays arguments (entry i of every array is point i);
  !> long enough for the vectorised stages, short enough for a block's temporaries (about
  !> 20 KiB) to stay in the L1 cache
  integer, parameter, public :: BLOCK_POINTS = 32

  public :: material_state_init
  public :: state_get_deformation, state_set_deformation
  public :: state_get_elastic_strain, state_set_elastic_strain

contains

  !> The undeformed, virgin state: F = I, be_bar = I, alpha = 0.
  pure subroutine material_state_init(hist)
    real(wp), intent(out) :: hist(NHIST)   !< history of one point
    hist = 0.0_wp
    call state_set_deformation(hist, IDENTITY)
    call state_set_elastic_strain(hist, IDENTITY)
    hist(HIST_ALPHA) = 0.0_wp
  end subroutine material_state_init

  !> F_n of a history.
  pure subroutine state_get_deformation(hist, f)
    real(wp), intent(in) :: hist(NHIST)   !< history of one point
    real(wp), intent(out) :: f(3,3)       !< deformation gradient
    f = reshape(hist(HIST_F:HIST_F+8), [3, 3])
  end subroutine state_get_deformation

  !> Store F in a history.
  pure subroutine state_set_deformation(hist, f)
    real(wp), intent(inout) :: hist(NHIST)   !< history of one point
    real(wp), intent(in) :: f(3,3)           !< deformation gradient
    hist(HIST_F:HIST_F+8) = reshape(f, [9])
  end subroutine state_set_deformation

  !> be_bar of a history as a symmetric 3x3 tensor.
  pure subroutine state_get_elastic_strain(hist, be_bar)
    real(wp), intent(in) :: hist(NHIST)    !< history of one point
    real(wp), intent(out) :: be_bar(3,3)   !< isochoric elastic left Cauchy-Green tensor
    call voigt_to_symmetric(hist(HIST_BE:HIST_BE+5), be_bar)
  end subroutine state_get_elastic_strain

  !> Store be_bar (symmetric; the upper triangle is used) in a history.
  pure subroutine state_set_elastic_strain(hist, be_bar)
    real(wp), intent(inout) :: hist(NHIST)   !< history of one point
    real(wp), intent(in) :: be_bar(3,3)      !< isochoric elastic left Cauchy-Green tensor
    call symmetric_to_voigt(be_bar, hist(HIST_BE:HIST_BE+5))
  end subroutine state_set_elastic_strain

end module mefem_material_state
