!> The run log's description of the model: counts, extent, parts with their element
!> formulation, material and mass, and the analysis controls, so users see what mefem
!> understood (a mass or an extent a factor 1000 off shows a unit slip).
module mefem_model_summary
  use mefem_kinds, only: wp
  use mefem_errors, only: say, warn
  use mefem_strings, only: itoa, rtoa
  use mefem_model, only: model_t
  use mefem_model_resolve, only: formulation_name, element_mass
  use mefem_read_materials, only: material_keyword
  implicit none
  private

  public :: print_model_summary, deck_stem

contains

  !> Print the model summary on rank 0.
  subroutine print_model_summary(model, read_seconds, memory_mib)
    type(model_t), intent(in) :: model     !< resolved model
    real(wp), intent(in) :: read_seconds   !< wall time spent reading and checking
    real(wp), intent(in) :: memory_mib     !< peak memory so far (MiB)
    integer :: p, count_p
    real(wp) :: mass(model%n_parts), extent(3)
    character(len=:), allocatable :: line
    call say('model: '//itoa(model%nodes%n)//' nodes, '//itoa(model%elements%n)// &
             ' elements, '//itoa(model%n_parts)//' parts, '//itoa(model%dimension)//'D'// &
             merge(' (plane strain)', '               ', model%dimension == 2))
    if (model%nodes%n > 0) then
      extent = maxval(model%nodes%x(:, 1:model%nodes%n), dim=2) - &
               minval(model%nodes%x(:, 1:model%nodes%n), dim=2)
      call say('  extent '//rtoa(extent(1))//' x '//rtoa(extent(2))//' x '// &
               rtoa(extent(3))//' (length units of the deck)')
    end if
    mass = part_masses(model)
    do p = 1, model%n_parts
      count_p = count(model%elements%part(1:model%elements%n) == p)
      line = '  part '//itoa(model%parts(p)%id)//': '//itoa(count_p)//' elements, '// &
             formulation_name(model, p)
      if (model%parts(p)%material > 0) line = line//', '// &
          material_keyword(model%materials(model%parts(p)%material)%kind)// &
          ' (material '//itoa(model%parts(p)%material_id)//'), mass '//rtoa(mass(p))
      if (len_trim(model%parts(p)%title) > 0) line = line//' "'//trim(model%parts(p)%title)//'"'
      call say(line)
      if (count_p == 0) call warn('part '//itoa(model%parts(p)%id)//' has no elements (a '// &
          'mesh file missing from the *INCLUDE list, or an element card with the wrong PID?)')
    end do
    line = '  total mass '//rtoa(sum(mass))//' (density x volume in the deck''s units'
    if (model%dimension == 2) line = line//', per unit thickness'
    call say(line//')')
    if (allocated(model%nodes%added_mass)) then
      if (any(model%nodes%added_mass > 0.0_wp)) call say('  added mass (*ELEMENT_MASS, '// &
          '*ELEMENT_MASS_PART) '//rtoa(sum(model%nodes%added_mass))//' at '// &
          itoa(count(model%nodes%added_mass > 0.0_wp))//' nodes')
    end if
    if (model%controls%have_termination) call say('  end time '// &
        rtoa(model%controls%end_time))
    call say('deck read and checked in '//rtoa(read_seconds)//' s, peak memory '// &
             rtoa(memory_mib)//' MiB per rank')
  end subroutine print_model_summary

  !> Mass of each part: density times the elements' volume (element_mass).
  function part_masses(model) result(mass)
    type(model_t), intent(in) :: model     !< resolved model
    real(wp) :: mass(model%n_parts)
    integer :: e, p
    mass = 0.0_wp
    do e = 1, model%elements%n
      p = model%elements%part(e)
      if (p > 0) mass(p) = mass(p) + element_mass(model, e)
    end do
  end function part_masses

  !> File name of a deck without directory and extension ("input/a.k" -> "a").
  function deck_stem(path) result(s)
    character(len=*), intent(in) :: path   !< deck path
    character(len=:), allocatable :: s
    integer :: slash, dot
    slash = index(path, '/', back=.true.)
    s = path(slash+1:)
    dot = index(s, '.', back=.true.)
    if (dot > 1) s = s(1:dot-1)
  end function deck_stem

end module mefem_model_summary
