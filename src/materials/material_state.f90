!> History (state) of one material point, shared by every material law.
!>
!> A point's history is a flat array hist(NHIST) so that element groups can store it as
!> hist(NHIST, n_points); the entries are addressed only through the named offsets below:
!> - HIST_CP .. HIST_CP+5: Cbar_p^-1 = J_n^(2/3) F_n^-1 be_bar_n F_n^-T, the isochoric
!>   inverse plastic right Cauchy-Green tensor of the last converged state (symmetric,
!>   det = 1), Voigt order xx yy zz xy yz zx; initially I. The plasticity law's elastic trial
!>   state at F is be_bar = J^(-2/3) F Cbar_p^-1 F^T (Simo 1992, the Lagrangian form of the
!>   same update: 6 entries instead of F_n and be_bar_n); the hyperelastic laws keep no
!>   history and leave it as it is;
!> - HIST_ALPHA: alpha_n, the equivalent plastic strain (0 for elastic laws);
!> - HIST_BACK .. HIST_BACK+5: the back stress of kinematic hardening (*MAT_003) in the frame
!>   that rotates with the material, R^T b R (F = R U), Voigt order; initially 0 (other laws
!>   leave it as it is);
!> - HIST_TEMPERATURE (= HIST_BACK: *MAT_JOHNSON_COOK has no back stress): the temperature
!>   rise T - TR from the plastic work; initially 0;
!> - HIST_DAMAGE (= HIST_BACK + 1, *MAT_JOHNSON_COOK): the damage sum of d alpha/eps_f of its
!>   failure model (D1-D5); the point fails at 1; initially 0;
!> - HIST_SPALL (= HIST_BACK + 2, *MAT_JOHNSON_COOK): POINT_INTACT (0), POINT_SPALLED (its
!>   spall criterion was met: compression only) or POINT_FAILED_KEPT (failed with EROD /= 0:
!>   pressure only); for good once set.
!> The laws read hist_old and write hist_new; the driver keeps hist_old until the step is
!> accepted (Newton converged), so a cut step simply discards hist_new.
module mefem_material_state
  use mefem_kinds, only: wp
  use mefem_tensor_algebra, only: IDENTITY, determinant, symmetric_to_voigt, voigt_to_symmetric
  implicit none
  private

  integer, parameter, public :: HIST_CP = 1       !< first of 6 entries: Cbar_p^-1 (Voigt)
  integer, parameter, public :: HIST_ALPHA = 7    !< equivalent plastic strain alpha_n
  integer, parameter, public :: HIST_BACK = 8     !< first of 6 entries: rotated back stress
  integer, parameter, public :: HIST_TEMPERATURE = HIST_BACK !< *MAT_015: T - TR
  integer, parameter, public :: HIST_DAMAGE = HIST_BACK + 1  !< *MAT_015: Johnson-Cook damage
  integer, parameter, public :: HIST_SPALL = HIST_BACK + 2   !< *MAT_015: POINT_* below
  real(wp), parameter, public :: POINT_INTACT = 0.0_wp, POINT_SPALLED = 1.0_wp, &
                                 POINT_FAILED_KEPT = 2.0_wp
  integer, parameter, public :: NHIST = 13        !< length of a point's history
  !> Points (cells) per block of the block kernels of the explicit cell loop: the leading
  !> dimension of their structure-of-arrays arguments (entry i of every array is point i);
  !> long enough for the vectorised stages, short enough for a block's temporaries (about
  !> 20 KiB) to stay in the L1 cache
  integer, parameter, public :: BLOCK_POINTS = 32

  public :: material_state_init, state_plastic_metric, state_elastic_strain

contains

  !> The undeformed, virgin state: Cbar_p^-1 = I, alpha = 0, no back stress.
  pure subroutine material_state_init(hist)
    real(wp), intent(out) :: hist(NHIST)   !< history of one point
    hist = 0.0_wp
    call symmetric_to_voigt(IDENTITY, hist(HIST_CP:HIST_CP+5))
    hist(HIST_ALPHA) = 0.0_wp
  end subroutine material_state_init

  !> Cbar_p^-1 of a history as a symmetric 3x3 tensor.
  pure subroutine state_plastic_metric(hist, cp_inverse)
    real(wp), intent(in) :: hist(NHIST)         !< history of one point
    real(wp), intent(out) :: cp_inverse(3,3)    !< isochoric inverse plastic right Cauchy-Green
    call voigt_to_symmetric(hist(HIST_CP:HIST_CP+5), cp_inverse)
  end subroutine state_plastic_metric

  !> The isochoric elastic left Cauchy-Green tensor be_bar = J^(-2/3) F Cbar_p^-1 F^T of a
  !> history at the deformation gradient F it was updated to (tests, post-processing).
  pure subroutine state_elastic_strain(hist, f, be_bar)
    real(wp), intent(in) :: hist(NHIST)    !< history of one point
    real(wp), intent(in) :: f(3,3)         !< deformation gradient (det > 0)
    real(wp), intent(out) :: be_bar(3,3)   !< isochoric elastic left Cauchy-Green tensor
    real(wp) :: cp_inverse(3,3)
    call state_plastic_metric(hist, cp_inverse)
    be_bar = determinant(f)**(-2.0_wp/3.0_wp)*matmul(f, matmul(cp_inverse, transpose(f)))
  end subroutine state_elastic_strain

end module mefem_material_state
