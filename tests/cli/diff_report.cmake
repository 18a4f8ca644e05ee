# SPDX-License-Identifier: MIT
# cmake -P diff_report.cmake -DSABLIER=... -DREF=tests/render/reference -DWORK=dir
# The page and report.json of `sablier diff BASELINE FRESH --report DIR` (docs/cli.md): the
# numbers the terminal prints (max difference, RMS, share of changed pixels) in both, a filter by
# status, zoom and blink, a PDF pair drawn as PNGs, relative paths, the same bytes from two runs,
# files written through NAME.tmp and a rename.
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK})

# A one-page PDF of 100x80 pt with a filled square of colour rgb at x, its cross-reference table
# at the right offsets.
function(make_pdf path rgb x)
  set(content "${rgb} rg ${x} 10 40 40 re f\n")
  string(LENGTH "${content}" clen)
  set(objects
      "<< /Type /Catalog /Pages 2 0 R >>"
      "<< /Type /Pages /Kids [3 0 R] /Count 1 >>"
      "<< /Type /Page /Parent 2 0 R /MediaBox [0 0 100 80] /Contents 4 0 R /Resources << >> >>"
      "<< /Length ${clen} >>\nstream\n${content}endstream")
  set(pdf "%PDF-1.4\n")
  set(xref "xref\n0 5\n0000000000 65535 f \n")
  set(k 1)
  foreach(obj IN LISTS objects)
    string(LENGTH "${pdf}" offset)
    string(LENGTH "${offset}" digits)
    math(EXPR pad "10 - ${digits}")
    string(REPEAT "0" ${pad} zeros)
    string(APPEND xref "${zeros}${offset} 00000 n \n")
    string(APPEND pdf "${k} 0 obj\n${obj}\nendobj\n")
    math(EXPR k "${k} + 1")
  endforeach()
  string(LENGTH "${pdf}" start)
  string(APPEND pdf "${xref}trailer\n<< /Size 5 /Root 1 0 R >>\nstartxref\n${start}\n%%EOF\n")
  file(WRITE ${path} "${pdf}")
endfunction()

file(MAKE_DIRECTORY ${WORK}/base ${WORK}/fresh)
make_pdf(${WORK}/base/p.pdf "1 0 0" 10)
make_pdf(${WORK}/fresh/p.pdf "0 0 1" 40)
file(COPY_FILE ${REF}/grains_fixed.png ${WORK}/base/a.png)
file(COPY_FILE ${REF}/grains_fixed.png ${WORK}/fresh/a.png)
file(COPY_FILE ${REF}/grains_fixed.png ${WORK}/base/gone.png)

# runs the diff into report folder r; stdout into out_r
function(run_diff r want)
  execute_process(COMMAND ${SABLIER} diff ${WORK}/base ${WORK}/fresh --report ${WORK}/${r}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL want)
    message(FATAL_ERROR "sablier diff --report ${r}: exit ${rc}, expected ${want}\n${out}\n${err}")
  endif()
  set(out_${r} "${out}" PARENT_SCOPE)
endfunction()
run_diff(r1 1)
run_diff(r2 1)

# the terminal's numbers for p.pdf
if(NOT out_r1 MATCHES "changed +p.pdf: ([0-9]+) pixels differ [(]max channel difference ([0-9]+), RMS ([0-9.e+-]+), ([0-9.e+-]+) % of the pixels[)]")
  message(FATAL_ERROR "stdout lacks p.pdf's numbers:\n${out_r1}")
endif()
set(pixels ${CMAKE_MATCH_1})
set(max ${CMAKE_MATCH_2})
set(rms ${CMAKE_MATCH_3})
set(share ${CMAKE_MATCH_4})

# report.json: the same numbers, the images relative to the report
file(READ ${WORK}/r1/report.json json)
string(JSON n LENGTH "${json}" figures)
math(EXPR last "${n} - 1")
set(p "")
foreach(k RANGE ${last})
  string(JSON name GET "${json}" figures ${k} name)
  if(name STREQUAL "p.pdf")
    set(p ${k})
  endif()
endforeach()
if(p STREQUAL "")
  message(FATAL_ERROR "report.json has no p.pdf:\n${json}")
endif()
foreach(pair "status=changed" "differing_pixels=${pixels}" "max_channel_diff=${max}"
             "baseline_image=baseline/p.pdf.png" "fresh_image=fresh/p.pdf.png"
             "diff_image=diff/p.pdf.png")
  string(REPLACE "=" ";" pair "${pair}")
  list(GET pair 0 key)
  list(GET pair 1 want)
  string(JSON got GET "${json}" figures ${p} ${key})
  if(NOT got STREQUAL want)
    message(FATAL_ERROR "report.json: p.pdf ${key} = ${got}, expected ${want}\n${json}")
  endif()
endforeach()
string(JSON width GET "${json}" figures ${p} width)
string(JSON height GET "${json}" figures ${p} height)
string(JSON got_rms GET "${json}" figures ${p} rms)
string(JSON got_share GET "${json}" figures ${p} changed_share)
# changed_share = differing_pixels / (width height), checked to 6 digits in integers
math(EXPR share_ppm "${pixels} * 1000000 / (${width} * ${height})")
string(REGEX MATCH "^0[.]([0-9]*)" frac "${got_share}")
string(SUBSTRING "${CMAKE_MATCH_1}000000" 0 6 got_ppm)
math(EXPR got_ppm "1${got_ppm} - 1000000")
math(EXPR delta "${got_ppm} - ${share_ppm}")
if(NOT got_rms GREATER 0 OR delta GREATER 1 OR delta LESS -1 OR NOT pixels GREATER 0)
  message(FATAL_ERROR "report.json: p.pdf rms ${got_rms}, changed_share ${got_share} "
                      "(${pixels} of ${width}x${height})\n${json}")
endif()
string(JSON base GET "${json}" baseline)
if(IS_ABSOLUTE "${base}")
  message(FATAL_ERROR "report.json names the baseline by an absolute path: ${base}")
endif()

# the PDF pair drawn as PNGs in the report folder
foreach(f baseline/p.pdf.png fresh/p.pdf.png diff/p.pdf.png baseline/p.pdf fresh/p.pdf)
  if(NOT EXISTS ${WORK}/r1/${f})
    message(FATAL_ERROR "the report lacks ${f}")
  endif()
endforeach()
file(READ ${WORK}/r1/baseline/p.pdf.png magic LIMIT 8 HEX)
if(NOT magic STREQUAL "89504e470d0a1a0a")
  message(FATAL_ERROR "baseline/p.pdf.png is no PNG (${magic})")
endif()

# index.html: the numbers, the filters, zoom and blink, the rendered PDF, self-contained
file(READ ${WORK}/r1/index.html html)
foreach(want "<b class=\"max\">${max}</b>" "<b class=\"rms\">${rms}</b>"
             "<b class=\"share\">${share} %</b>" "<img src=\"baseline/p.pdf.png\""
             "<img src=\"fresh/p.pdf.png\"" "<img src=\"diff/p.pdf.png\""
             "data-fresh=\"fresh/p.pdf.png\"" "<button class=\"blink\"" "id=\"zoom\""
             "name=\"viewport\"" "<input type=\"checkbox\" value=\"changed\" checked>"
             "<input type=\"checkbox\" value=\"missing\" checked>"
             "<input type=\"checkbox\" value=\"identical\">"
             "data-status=\"missing\"" "data-status=\"identical\"")
  string(FIND "${html}" "${want}" at)
  if(at LESS 0)
    message(FATAL_ERROR "index.html lacks ${want}:\n${html}")
  endif()
endforeach()
foreach(banned "http://" "https://" "<link" "${WORK}" "href=\"/" "src=\"/")
  string(FIND "${html}${json}" "${banned}" at)
  if(NOT at LESS 0)
    message(FATAL_ERROR "the report holds `${banned}` (an absolute path or the network)")
  endif()
endforeach()

# two runs: the same bytes
foreach(f index.html report.json baseline/p.pdf.png diff/p.pdf.png)
  file(SHA256 ${WORK}/r1/${f} h1)
  file(SHA256 ${WORK}/r2/${f} h2)
  if(NOT h1 STREQUAL h2)
    message(FATAL_ERROR "two runs wrote different ${f}")
  endif()
endforeach()
file(GLOB_RECURSE tmp ${WORK}/r1/*.tmp)
if(tmp)
  message(FATAL_ERROR "the report left temporary files: ${tmp}")
endif()

# written through NAME.tmp: a folder in the way of the temporary name stops that file, and the
# name is not left half written
foreach(f index.html baseline/p.pdf.png)
  string(MAKE_C_IDENTIFIER ${f} r)
  file(MAKE_DIRECTORY ${WORK}/${r}/${f}.tmp)
  run_diff(${r} 2)
  if(EXISTS ${WORK}/${r}/${f})
    message(FATAL_ERROR "${f} was written although ${f}.tmp could not be")
  endif()
endforeach()
