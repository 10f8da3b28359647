!> The run log's description of the model: counts, parts with their element formulation
!> and material, and the analysis controls, so users see what mefem understood.
module mefem_model_summary
  use mefem_kinds, only: wp
  use mefem_errors, only: say, warn
  use mefem_strings, only: itoa, rtoa
  use mefem_model, only: model_t
  use mefem_model_resolve, only: formulation_name
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
    character(len=:), allocatable :: line
    call say('model: '//itoa(model%nodes%n)//' nodes, '//itoa(model%elements%n)// &
             ' elements, '//itoa(model%n_parts)//' parts, '//itoa(model%dimension)//'D'// &
             merge(' (plane strain)', '               ', model%dimension == 2))
    do p = 1, model%n_parts
      count_p = count(model%elements%part(1:model%elements%n) == p)
      line = '  part '//itoa(model%parts(p)%id)//': '//itoa(count_p)//' elements, '// &
             formulation_name(model, p)
      if (model%parts(p)%material > 0) line = line//', '// &
          material_keyword(model%materials(model%parts(p)%material)%kind)// &
          ' (material '//itoa(model%parts(p)%material_id)//')'
      if (len_trim(model%parts(p)%title) > 0) line = line//' "'//trim(model%parts(p)%title)//'"'
      call say(line)
      if (count_p == 0) call warn('part '//itoa(model%parts(p)%id)//' has no elements (a '// &
          'mesh file missing from the *INCLUDE list, or an element card with the wrong PID?)')
    end do
    if (model%controls%have_termination) call say('  end time '// &
        rtoa(model%controls%end_time))
    call say('deck read and checked in '//rtoa(read_seconds)//' s, peak memory '// &
             rtoa(memory_mib)//' MiB per rank')
  end subroutine print_model_summary

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
